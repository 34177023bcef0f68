"""Obstacles in the plane (discs, polygons and occupancy images), their exact clearance, and the certificate that a
tube misses them.

The clearance of a point is its distance to the nearest obstacle, 0 on or inside one: a disc's is
max(0, |p - c| - r), a polygon's 0 inside it (even-odd rule) and otherwise the distance to its nearest edge, an
occupancy image's the distance to the nearest of its occupied pixels, each a closed square
(`vtube_planning.geometry.occupancy`: a SLAM or ROS ``map_server`` map, read with ROS's conventions). All
are exact and 1-Lipschitz in the point. That is what `obstacle_certificate` rests on: along the centre curve
(unit speed) the clearance minus the half-width changes by at most 1 + max|lambda'| per metre, so samples ``h``
apart that each keep more than (1 + max|lambda'|) h / 2 prove that no cross-section anywhere meets an obstacle (a
cross-section of half-length lambda lies in the free disc of radius clearance around its centre point).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vtube_planning._validate import is_real
from vtube_planning.errors import SceneError
from vtube_planning.geometry._shapes import Shapes
from vtube_planning.geometry.occupancy import OccupancyImage, image_from_entry
from vtube_planning.geometry.tube import VirtualTube

FloatArray = NDArray[np.float64]

_NEAR = 256
"""Consecutive points that share one choice of the obstacles that may be nearest (`Obstacles.clearance`)."""


@dataclass(frozen=True)
class Disc:
    """A disc obstacle: centre (x, y) and radius, in metres."""

    center_m: tuple[float, float]
    radius_m: float

    def __post_init__(self) -> None:
        if len(self.center_m) != 2 or not all(is_real(v) for v in (*self.center_m, self.radius_m)):
            msg = f'a disc needs center_m = [x, y] and radius_m, finite numbers; got {self}.'
            raise SceneError(msg)
        if self.radius_m <= 0.0:
            msg = f'a disc needs radius_m > 0; got {self.radius_m}.'
            raise SceneError(msg)


@dataclass(frozen=True)
class Polygon:
    """A polygon obstacle: its vertices (x, y) in metres, in order (closed implicitly; inside by the even-odd
    rule)."""

    vertices_m: tuple[tuple[float, float], ...]

    def __post_init__(self) -> None:
        if len(self.vertices_m) < 3 or any(len(v) != 2 for v in self.vertices_m):
            msg = f'a polygon needs vertices_m = [[x, y], ...] with at least 3 vertices; got {self.vertices_m}.'
            raise SceneError(msg)
        if not all(is_real(c) for v in self.vertices_m for c in v):
            msg = f'polygon vertices must be finite numbers; got {self.vertices_m}.'
            raise SceneError(msg)
        xy = np.array(self.vertices_m, dtype=float)
        area = 0.5 * float(np.dot(xy[:, 0], np.roll(xy[:, 1], -1)) - np.dot(xy[:, 1], np.roll(xy[:, 0], -1)))
        if abs(area) < 1e-12:
            msg = f'a polygon needs a non-zero area; its vertices {self.vertices_m} lie on a line.'
            raise SceneError(msg)


@dataclass(frozen=True)
class Obstacles:
    """The obstacles of a scene: discs, polygons and occupancy images."""

    discs: tuple[Disc, ...] = ()
    polygons: tuple[Polygon, ...] = ()
    images: tuple[OccupancyImage, ...] = ()

    def __bool__(self) -> bool:
        return bool(self.discs or self.polygons or self.images)

    def clearance(self, points_m: FloatArray) -> FloatArray:
        """Distance (k,) of (k, 2) points to the nearest obstacle, 0 on or inside one; inf without obstacles. Each
        block of consecutive points measures only the obstacles that may be nearest to some of them
        (`Shapes.near <vtube_planning.geometry._shapes.Shapes.near>`, exact)."""
        points = np.asarray(points_m, dtype=float).reshape(-1, 2)
        out = np.full(points.shape[0], np.inf)
        shapes = self._shapes
        for start in range(0, points.shape[0], _NEAR):
            block = points[start : start + _NEAR]
            out[start : start + _NEAR] = shapes.near(block).clearance(block)
        for image in self.images:
            out = np.minimum(out, image.clearance(points))
        return out

    def inside(self, points_m: FloatArray) -> NDArray[np.bool_]:
        """Whether each of (k, 2) points lies in an obstacle (on a disc's rim counts), (k,); each obstacle tests
        only the points in its bounding box (found by bisection among the points sorted by x)."""
        points = np.asarray(points_m, dtype=float).reshape(-1, 2)
        hit = np.zeros(points.shape[0], dtype=bool)
        order = np.argsort(points[:, 0], kind='stable')  # a grid's nodes come sorted: linear time
        xs = points[order, 0]

        def in_box(low: FloatArray, high: FloatArray) -> NDArray[np.intp]:
            among = order[np.searchsorted(xs, low[0], side='left') : np.searchsorted(xs, high[0], side='right')]
            keep: NDArray[np.intp] = among[(points[among, 1] >= low[1]) & (points[among, 1] <= high[1])]
            return keep

        for disc in self.discs:
            (cx, cy), r = disc.center_m, disc.radius_m
            near = in_box(np.array([cx - 2 * r, cy - 2 * r]), np.array([cx + 2 * r, cy + 2 * r]))  # then exactly:
            near = near[(np.abs(points[near, 0] - cx) <= r) & (np.abs(points[near, 1] - cy) <= r)]
            hit[near] |= np.hypot(points[near, 0] - cx, points[near, 1] - cy) <= r
        shapes = self._shapes
        for k in range(len(self.polygons)):
            near = in_box(shapes.low[k], shapes.high[k])
            hit[near] |= shapes.polygon(k).clearance(points[near]) == 0.0
        for image in self.images:
            hit |= image.inside(points)
        return hit

    def unknown_share(self, tube: VirtualTube, across: int = 41) -> float | None:
        """The share of the tube's area (sampled: half a pixel along, ``across`` points across, weighted by the
        half-width) on unknown cells of images that count them free (``unknown = "free"``); None: no image does."""
        free = [image for image in self.images if image.unknown_free]
        if not free:
            return None
        step = max(0.5 * min(image.resolution_m for image in free), tube.length_m / 20000.0)
        l_m = np.linspace(0.0, tube.length_m, math.ceil(tube.length_m / step) + 1)
        half = np.asarray(tube.half_width(l_m), dtype=float)
        offsets = np.linspace(-1.0, 1.0, across)[None, :, None] * half[:, None, None]
        points = (tube.center_at(l_m)[:, None, :] + offsets * tube.normal(l_m)[:, None, :]).reshape(-1, 2)
        on = np.zeros(points.shape[0], dtype=bool)
        for image in free:
            on |= image.on_unknown(points)
        weights = np.repeat(half, across)
        return float((weights * on).sum() / weights.sum())

    @cached_property
    def _shapes(self) -> Shapes:
        discs = [(d.center_m, d.radius_m) for d in self.discs]
        return Shapes.of(discs, [np.array(p.vertices_m, dtype=float) for p in self.polygons])

    def outlines(self, points_per_disc: int = 48) -> tuple[FloatArray, ...]:
        """Each obstacle's closed outline (2, K) for drawing where no patch type exists (the testbed's figure): a
        polygon's vertices, a disc's ``points_per_disc`` points on its circle; the first point is repeated last.
        Occupancy images have none (their pixels are drawn as an image where a figure is ours, ``plots``)."""
        angle = np.linspace(0.0, 2.0 * math.pi, points_per_disc + 1)
        circles = [
            np.array(d.center_m)[:, None] + d.radius_m * np.stack([np.cos(angle), np.sin(angle)]) for d in self.discs
        ]
        shapes = [np.array((*p.vertices_m, p.vertices_m[0]), dtype=float).T for p in self.polygons]
        return (*circles, *shapes)

    def table(self, folder: Path | None = None) -> dict[str, list[dict[str, Any]]]:
        """The ``[obstacles]`` table of a scene file in ``folder`` (`obstacles_from_table` reads it back):
        an image's ``file`` relative to ``folder`` when it can be, else absolute (absolute without ``folder``)."""
        table: dict[str, list[dict[str, Any]]] = {}
        if self.discs:
            table['discs'] = [{'center_m': list(d.center_m), 'radius_m': d.radius_m} for d in self.discs]
        if self.polygons:
            table['polygons'] = [{'vertices_m': [list(v) for v in p.vertices_m]} for p in self.polygons]
        if self.images:
            table['images'] = [image.entry(folder) for image in self.images]
        return table


NO_OBSTACLES = Obstacles()
"""A scene without obstacles."""


def obstacles_from_table(table: object, folder: Path | None = None) -> Obstacles:
    """The obstacles of a scene file's ``[obstacles]`` table (``discs = [{center_m, radius_m}]``, ``polygons =
    [{vertices_m}]``, ``images = [{file, resolution_m, origin_m, occupied_thresh}]``, an image's ``file`` relative
    to ``folder``, the scene file's); a wrong key or value raises [`SceneError`][vtube_planning.errors.SceneError]
    naming it."""
    if not isinstance(table, Mapping):
        msg = '[obstacles] must be a table with discs = [...], polygons = [...] and/or images = [...].'
        raise SceneError(msg)
    unknown = set(table) - {'discs', 'polygons', 'images'}
    if unknown:
        msg = f'unknown key(s) {sorted(unknown)} in [obstacles]; it takes discs, polygons and images.'
        raise SceneError(msg)
    for kind in ('discs', 'polygons', 'images'):
        if not isinstance(table.get(kind, []), list):
            msg = f'[obstacles] {kind} must be a list [...] of tables; got {table[kind]!r}.'
            raise SceneError(msg)
    discs = [_entry(d, {'center_m', 'radius_m'}, 'discs') for d in table.get('discs', [])]
    polygons = [_entry(p, {'vertices_m'}, 'polygons') for p in table.get('polygons', [])]
    return Obstacles(
        tuple(Disc(tuple(d['center_m']), d['radius_m']) for d in discs),
        tuple(Polygon(tuple(tuple(v) for v in p['vertices_m'])) for p in polygons),
        tuple(image_from_entry(entry, folder) for entry in table.get('images', [])),
    )


def certified_obstacles(tube: VirtualTube, table: object, folder: Path | None = None) -> Obstacles:
    """The obstacles of an ``[obstacles]`` table (images read relative to ``folder``), refused
    ([`SceneError`][vtube_planning.errors.SceneError]) unless ``tube`` misses them all."""
    obstacles = obstacles_from_table(table, folder)
    certificate = obstacle_certificate(tube, obstacles)
    if not certificate.clear:
        msg = f'the tube meets an obstacle: {certificate}; move or narrow the tube.'
        raise SceneError(msg)
    return obstacles


def _entry(entry: object, keys: set[str], kind: str) -> Mapping[str, Any]:
    if not isinstance(entry, Mapping) or set(entry) != keys:
        msg = f'each of [obstacles] {kind} needs exactly the keys {sorted(keys)}; got {entry!r}.'
        raise SceneError(msg)
    return entry


@dataclass(frozen=True)
class ObstacleCertificate:
    """Whether a tube misses the obstacles, proved on samples ``step_m`` apart: the smallest margin (clearance of
    the centre point minus the half-width) found, where, and the margin the proof needs (`obstacle_certificate`)."""

    clear: bool
    margin_m: float
    needed_m: float
    l_m: float
    point_m: tuple[float, float]
    step_m: float

    def __str__(self) -> str:
        x, y = self.point_m
        return (
            f'at l = {self.l_m:.3f} m, ({x:.3f}, {y:.3f}), the nearest obstacle is {self.margin_m:.4f} m beyond the '
            f'tube wall ({self.needed_m:.4f} m needed between samples {self.step_m:.4f} m apart)'
        )


def obstacle_certificate(tube: VirtualTube, obstacles: Obstacles, step_m: float | None = None) -> ObstacleCertificate:
    """Prove (or refute) that no cross-section of ``tube`` meets ``obstacles`` (module doc): samples ``step_m``
    apart (default: 1/8 of the narrowest half-width, at most 1 cm) must each keep a margin of at least
    (1 + max|lambda'|) step / 2."""
    narrowest = float(np.min(tube.half_width(np.linspace(0.0, tube.length_m, 2001))))
    step = float(step_m) if step_m is not None else min(0.01, narrowest / 8.0)
    n = max(2, math.ceil(tube.length_m / step) + 1)
    l_m = np.linspace(0.0, tube.length_m, n)
    step = tube.length_m / (n - 1)
    centers = tube.center_at(l_m)
    margin = obstacles.clearance(centers) - tube.half_width(l_m)
    needed = (1.0 + tube.width.max_abs_slope()) * step / 2.0
    k = int(np.argmin(margin))
    point = (float(centers[k, 0]), float(centers[k, 1]))
    return ObstacleCertificate(bool(margin[k] >= needed), float(margin[k]), needed, float(l_m[k]), point, step)
