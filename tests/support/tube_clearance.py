"""An independent check that a tube misses obstacles: every cross-section sampled (1 cm along, 101 points across),
discs by the distance to their centres, polygons by matplotlib's point-in-polygon and the distance to each edge,
none of it from :mod:`vtube_planning.geometry.obstacles`. Used by the tests and ``benchmarks/tube_generation.py``."""

from __future__ import annotations

import numpy as np
from matplotlib.path import Path as MplPath

from vtube_planning.geometry.obstacles import Obstacles
from vtube_planning.geometry.tube import VirtualTube


def tube_points(tube: VirtualTube, step_m: float = 0.01, across: int = 101) -> np.ndarray:
    """Every cross-section ``step_m`` apart, ``across`` points across each, (k, 2)."""
    l_m = np.arange(0.0, tube.length_m + step_m, step_m).clip(max=tube.length_m)
    centers, normals, half = tube.center_at(l_m), tube.normal(l_m), tube.half_width(l_m)
    fractions = np.linspace(-1.0, 1.0, across)
    return (centers[:, None, :] + (half[:, None] * fractions)[:, :, None] * normals[:, None, :]).reshape(-1, 2)


def closest_approach(tube: VirtualTube, obstacles: Obstacles, step_m: float = 0.01, across: int = 101) -> float:
    """The smallest distance from a sampled point of the tube to an obstacle, 0 when one lies inside one."""
    points = tube_points(tube, step_m, across)
    closest = np.inf
    for disc in obstacles.discs:
        closest = min(closest, max(0.0, float(np.hypot(*(points - disc.center_m).T).min()) - disc.radius_m))
    for polygon in obstacles.polygons:
        xy = np.array(polygon.vertices_m)
        if MplPath(xy).contains_points(points).any():
            return 0.0
        for a, b in zip(xy, np.roll(xy, -1, axis=0), strict=True):
            d = b - a
            t = np.clip(((points - a) @ d) / (d @ d), 0.0, 1.0)
            closest = min(closest, float(np.hypot(*(points - a - t[:, None] * d).T).min()))
    return float(closest)
