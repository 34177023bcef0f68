"""A regular virtual tube from an obstacle map: a path through the free space, lines and arcs, a width under the
clearance, certified.

The paper plans on a tube generated beforehand from the obstacles ([b12]); this is vtube's own generator
(``docs/theory.md`` §10 gives the reasoning). The steps:

1. *Clearance* on a grid of ``resolution_m``: each node's distance to the nearest node inside an obstacle (or
   whose cell meets an occupancy image's occupied pixel: pixels smaller than a cell are not missed), less half a
   cell's diagonal (``scipy.ndimage.distance_transform_edt``), or to the map's edge: a lower bound that
   guides the search (what is certified uses the exact clearance,
   `clearance`).
2. *Path*: the cheapest 8-connected grid path from start to goal through the nodes that leave room for the
   narrowest tube (``half_width_min_m`` + ``margin_m``), each step costing its length times 1 + lambda_max /
   clearance, so the path keeps to the middle of passages (Dijkstra, ``scipy.sparse.csgraph``). No path: refused
   with the widest passage there is (the largest room for which start and goal stay connected).
3. *Centre curve*: the path pulled straight (``_pulled_straight``) or, if that one cannot be rounded,
   simplified (`_simplified`), then each corner rounded by the largest circular arc that fits in its share of the
   neighbouring segments and keeps the room; a corner whose arc would be below ``turn_radius_min_m`` is taken out
   of the grid and another route searched (`ROUTES` in all), then refused with the first such corner. Lines and arcs: an exact
   [`ArcPath`][vtube_planning.geometry.centerline.ArcPath], written as ``pieces`` in a scene file.
4. *Width*: under the bound min(clearance - margin - the certificate's share, ``curvature_share`` / |kappa|,
   ``half_width_max_m``), as ramps and constant parts between knots about 8 grid cells apart, with |lambda'| at
   most ``slope_max`` (`width_under`).
5. *Certificate*: [`VirtualTube`][vtube_planning.geometry.tube.VirtualTube] checks regularity (lambda |kappa| < 1, no
   crossing cross-sections), `obstacle_certificate` proves that no
   cross-section meets an obstacle between its samples, and every boundary keeps ``margin_m`` inside the map.

Steps 1-3 are `vtube_planning.geometry.from_maps.centre_path`'s. Every refusal is a
[`TubeGenerationError`][vtube_planning.errors.TubeGenerationError] naming the place and the reason.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import TubeError, TubeGenerationError
from vtube_planning.geometry.centerline import ArcPath
from vtube_planning.geometry.from_maps.centre_path import CornerError, SearchGrid, centre_curve
from vtube_planning.geometry.from_maps.tube_spec import TubeSpec
from vtube_planning.geometry.obstacles import ObstacleCertificate, Obstacles, obstacle_certificate
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthProfile, width_under

FloatArray = NDArray[np.float64]
__all__ = ['GeneratedTube', 'TubeSpec', 'generate_tube']


@dataclass(frozen=True)
class GeneratedTube:
    """A certified tube and how it was made: the tube, the path's vertices, the obstacle certificate, the obstacles
    it was generated among, the lead held along the headings."""

    tube: VirtualTube
    path_m: FloatArray
    certificate: ObstacleCertificate
    obstacles: Obstacles = field(default_factory=Obstacles)
    lead_m: float = 0.0
    """The straight lead held along the headings given (the spec's, or the one fitted); 0 without a heading."""


def generate_tube(spec: TubeSpec, name: str = 'generated') -> GeneratedTube:
    """The tube of ``spec`` (module doc), certified; [`TubeGenerationError`][vtube_planning.errors.TubeGenerationError]
    when there is none. A heading without ``lead_m`` gets the shortest of `LEADS` that gives a tube."""
    if spec.headed and spec.lead_m == 0.0:
        return _with_a_lead(spec, name)
    corners, center = _routed(SearchGrid(spec))
    even = np.linspace(0.0, center.length_m, max(2, math.ceil(center.length_m / spec.sample_m) + 1))
    joints = center.breakpoints[1:-1]  # both sides of every joint: an arc shorter than the spacing is sampled
    samples = np.unique(np.concatenate([even, joints - 1e-9, joints + 1e-9]))
    width = _width_parts(center, samples, spec)
    try:
        tube = VirtualTube(center, width, name=name)
    except TubeError as err:
        msg = f'the generated tube is not regular: {err}'
        raise TubeGenerationError(msg) from err
    certificate = obstacle_certificate(tube, spec.obstacles)
    if not certificate.clear:
        msg = f'the generated tube meets an obstacle: {certificate}'
        raise TubeGenerationError(msg)
    for points in tube.boundaries(samples):
        edge = spec.bounds.clearance(points) - spec.bounds.margin_m
        if edge.min() < -1e-9:
            k = int(np.argmin(edge))
            msg = f'the generated tube leaves the map at ({points[k, 0]:.3f}, {points[k, 1]:.3f}).'
            raise TubeGenerationError(msg)
    return GeneratedTube(tube, corners, certificate, spec.obstacles, spec.lead_m if spec.headed else 0.0)


LEADS = (0.5, 1.0, 1.5, 2.0, 3.0)
"""The leads tried for a heading given without ``lead_m``, in turn radii (``turn_radius_min_m``, at least four grid
cells): the arc that turns off a lead takes at most half of its 2 ``lead_m``, so a lead of r tan(turn / 2) lets the
smallest arc turn off it."""


def _with_a_lead(spec: TubeSpec, name: str) -> GeneratedTube:
    """The tube of ``spec`` with the shortest lead of `LEADS` that gives one (the ends fitted as the corners are);
    none: the shortest lead's refusal, and what to give."""
    unit = max(spec.turn_radius_min_m, 4.0 * spec.resolution_m)
    refusals = []
    for factor in LEADS:
        try:
            return generate_tube(replace(spec, lead_m=factor * unit), name)
        except TubeGenerationError as err:
            refusals.append(err)
    msg = (
        f'no lead from {LEADS[0] * unit:g} to {LEADS[-1] * unit:g} m holds the heading given (lead_m was not given, '
        f'so the generator tried {len(LEADS)}): with {LEADS[0] * unit:g} m, {refusals[0]} Give lead_m, turn the '
        'heading towards the route, or leave it out.'
    )
    raise TubeGenerationError(msg)


ROUTES = 6
"""The routes `_routed` tries before it refuses a corner."""


def _routed(grid: SearchGrid) -> tuple[FloatArray, ArcPath]:
    """The corners and centre curve of the cheapest route whose corners can be rounded: a corner no arc rounds (next
    to a wall, say, where a person would go between the pillars) is taken out of the grid (a disc of the tube's room
    about it) and the route searched again, up to `ROUTES` routes; then the first refusal."""
    refusals: list[CornerError] = []
    while True:
        try:
            path = grid.path()
        except TubeGenerationError:
            if refusals:  # no other route: the first corner's refusal says what to change
                raise refusals[0] from None
            raise
        try:
            return centre_curve(path, grid)
        except CornerError as err:
            refusals.append(err)
            if len(refusals) == ROUTES:
                raise refusals[0] from None
            grid.block(err.corner_m, grid.spec.room_m)


def _width_parts(center: ArcPath, l_m: FloatArray, spec: TubeSpec) -> WidthProfile:
    """A width under the bound (module doc, step 4) at the samples ``l_m``, with knots about 8 grid cells apart
    (`width_under`)."""
    positions, tangents, kappa = center.frame(l_m)
    normals = np.column_stack([-tangents[:, 1], tangents[:, 0]])
    with np.errstate(divide='ignore'):
        curvature_bound = np.where(np.abs(kappa) > 0.0, spec.curvature_share / np.abs(kappa), np.inf)
    bound = np.minimum.reduce(
        [
            spec.obstacles.clearance(positions) - 0.5 * spec.sample_m - spec.margin_m - spec.certificate_share_m,
            spec.edge_reach(positions, normals) - 0.5 * spec.sample_m,
            curvature_bound,
            np.full(l_m.size, spec.half_width_max_m),
        ]
    )
    if bound.min() < spec.half_width_min_m:
        k = int(np.argmin(bound))
        x, y = positions[k]
        msg = (
            f'at l = {l_m[k]:.3f} m, ({x:.3f}, {y:.3f}), the centre curve leaves room for a half-width of '
            f'{max(bound[k], 0.0):.3f} m, less than half_width_min_m = {spec.half_width_min_m}'
            + (' (the curve turns too tightly there)' if curvature_bound[k] <= bound[k] else '')
            + '; lower half_width_min_m or margin_m, or move the obstacles apart.'
        )
        raise TubeGenerationError(msg)
    cells = max(1, math.ceil(center.length_m / (8.0 * spec.resolution_m)))
    return width_under(l_m, bound, spec.slope_max, cells)
