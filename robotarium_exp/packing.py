"""Where a start formation may stand, how many robots it can hold at most, and a packing in no rows.

The start region (`start_region`) is where the design's formations may put a robot (``docs/theory.md`` §12): at
least `WALL_CLEARANCE_M` from the walls (or from their lines continued behind the entrance, where the entry queue
stands), inside the box the testbed initializes robots in, and before the tube's first narrowing. Robots stand the
initializer's spacing d = 0.4 m apart.

- `packing_bound`: Oler's inequality (N. Oler, *An inequality in the geometry of numbers*, Acta Math. 105, 1961)
  on the region's convex hull K bounds any set of points at least d apart in K,
  N <= (2 / sqrt 3) A(K) / d^2 + P(K) / (2 d) + 1. More robots than that cannot start, in any layout: a physical
  refusal under these rules.
- `packed_poses`: the robots placed by penalty optimisation (L-BFGS-B from seeded random starts over their arc
  lengths and lateral places), for a tube where rows, the entry queue and staggered rows all reach the narrowing.
  Deterministic; accepted only when every pair keeps the spacing and every robot the region, exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import minimize
from scipy.spatial import ConvexHull, QhullError

from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import first_narrowing

FloatArray = NDArray[np.float64]

WALL_CLEARANCE_M = 0.1
"""Between a robot of the start formation and a wall: the body's radius (0.055 m) and 0.045 m to move."""
QUEUE_BEFORE_NARROWING_M = 0.01
"""A start formation's front robot stands at least this far before the narrowing's start (the fit verdict's rule,
with room for the flight data's rounding)."""
QUEUE_BEHIND_M = 3.0
"""How far behind the entrance the region reaches (the box is 2.75 m long)."""
REGION_SAMPLES = 2001
"""Arc lengths sampled over the region (about 2 mm apart on the sweep's tubes)."""
PACK_RESTARTS = 12
"""Seeded random starts `packed_poses` tries before it gives up."""
PACK_MARGIN_M = 0.002
"""The optimisation aims this far beyond the spacing and this far inside the box, so that the exact check passes."""


@dataclass(frozen=True)
class StartRegion:
    """The region sampled at arc lengths ``l_m`` (from `QUEUE_BEHIND_M` behind the entrance to the narrowing, less
    `QUEUE_BEFORE_NARROWING_M`, or the exit): the centre ``center_m`` (K, 2), the unit normal ``normal`` (K, 2) and
    the half room ``room_m`` (K,) a robot has either side of the centre line."""

    l_m: FloatArray
    center_m: FloatArray
    normal: FloatArray
    room_m: FloatArray

    def points(self, l_m: FloatArray, across: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Positions (n, 2) of robots at arc lengths ``l_m`` and ``across`` in [-1, 1] of the room, and their
        derivatives by the two (n, 2) each: the tables interpolated linearly."""
        k = np.clip(np.searchsorted(self.l_m, l_m) - 1, 0, self.l_m.size - 2)
        step = self.l_m[k + 1] - self.l_m[k]
        w = ((l_m - self.l_m[k]) / step)[:, None]
        center = self.center_m[k] + w * (self.center_m[k + 1] - self.center_m[k])
        normal = self.normal[k] + w * (self.normal[k + 1] - self.normal[k])
        room = (self.room_m[k] + w[:, 0] * (self.room_m[k + 1] - self.room_m[k]))[:, None]
        lateral = across[:, None] * room
        along = (self.center_m[k + 1] - self.center_m[k]) / step[:, None]
        along = along + lateral * (self.normal[k + 1] - self.normal[k]) / step[:, None]
        along = along + across[:, None] * normal * ((self.room_m[k + 1] - self.room_m[k]) / step)[:, None]
        return center + lateral * normal, along, room * normal

    def inside_box(self, points_m: FloatArray) -> NDArray[np.bool_]:
        """Which of (n, 2) points lie inside the box the testbed initializes robots in."""
        inside: NDArray[np.bool_] = np.all(np.abs(points_m) <= np.array(ROBOTARIUM.ic_box_m), axis=1)
        return inside


def start_region(tube: VirtualTube) -> StartRegion:
    """The start region of ``tube`` (module doc)."""
    narrowing = first_narrowing(*tube.width.knots)
    end = narrowing.start_m - QUEUE_BEFORE_NARROWING_M if narrowing is not None else tube.length_m
    l_m = np.linspace(-QUEUE_BEHIND_M, end, REGION_SAMPLES)
    return StartRegion(l_m, tube.center_at(l_m), tube.normal(l_m), room_at(tube, l_m))


def room_at(tube: VirtualTube, l_m: FloatArray) -> FloatArray:
    """The half room a robot has either side of the centre line at arc lengths ``l_m`` (behind the entrance, the
    entrance's)."""
    room: FloatArray = np.maximum(
        np.asarray(tube.half_width(np.maximum(l_m, 0.0)), dtype=float) - WALL_CLEARANCE_M, 0.0
    )
    return room


def packing_bound(tube: VirtualTube) -> int:
    """Oler's bound (module doc) on how many robots can start in ``tube``'s start region; 0 where no point of it
    lies inside the box."""
    return _oler_bound(start_region(tube))


def _oler_bound(region: StartRegion) -> int:
    """`packing_bound` of a sampled start region."""
    across = np.linspace(-1.0, 1.0, 81)
    points = (
        region.center_m[:, None, :] + across[None, :, None] * region.room_m[:, None, None] * region.normal[:, None, :]
    ).reshape(-1, 2)
    return oler_bound(points[region.inside_box(points)], ROBOTARIUM.ic_spacing_m)


def oler_bound(points_m: FloatArray, spacing_m: float) -> int:
    """Oler's bound (module doc) on how many points ``spacing_m`` apart fit in the convex hull of ``points_m``
    (n, 2): 0 for no point; on a segment (the hull has no area), its length over the spacing, plus one."""
    if points_m.shape[0] == 0:
        return 0
    try:
        hull = ConvexHull(points_m)
    except QhullError:
        return math.floor(float(np.hypot(*np.ptp(points_m, axis=0))) / spacing_m + 1.0)  # collinear: a segment
    area, perimeter = float(hull.volume), float(hull.area)
    return math.floor(2.0 / math.sqrt(3.0) * area / spacing_m**2 + perimeter / (2.0 * spacing_m) + 1.0)


def packed_poses(tube: VirtualTube, n_robots: int) -> FloatArray | None:
    """Poses (3, N) of ``n_robots`` in the start region, every pair at least the spacing apart, headings along the
    tube, placed by `_packed` (None: none found, or more than `packing_bound`)."""
    found = _packed(tube, n_robots)
    if found is None:
        return None
    l_m, points = np.array(found[0]), np.array(found[1])
    tangent = tube.tangent(l_m)
    poses: FloatArray = np.array([points[:, 0], points[:, 1], np.arctan2(tangent[:, 1], tangent[:, 0])])
    return poses


Packing = tuple[tuple[float, ...], tuple[tuple[float, float], ...]]
_PACKINGS: dict[tuple[str, int], Packing | None] = {}
"""`_packed`'s answers by the tube's fingerprint and N: the fit verdict asks for every N below a refused one."""


def _packed(tube: VirtualTube, n_robots: int) -> Packing | None:
    """Arc lengths and positions (front first) of a packing of ``n_robots`` (cached in `_PACKINGS`)."""
    key = (tube.fingerprint(), n_robots)
    if key not in _PACKINGS:
        _PACKINGS[key] = _search(tube, n_robots)
    return _PACKINGS[key]


def packed_in_window(tube: VirtualTube, n_robots: int, first_m: float, last_m: float, restarts: int) -> bool:
    """Whether `_search`'s first ``restarts`` starts place ``n_robots`` between arc lengths ``first_m`` and
    ``last_m`` of the start region (a witness for `robotarium_exp.packing_proof`)."""
    return _search(tube, n_robots, (first_m, last_m), restarts) is not None


def _search(
    tube: VirtualTube, n_robots: int, window: tuple[float, float] | None = None, restarts: int = PACK_RESTARTS
) -> Packing | None:
    """``restarts`` seeded starts of the penalty optimisation (between the arc lengths of ``window``, if given),
    the first exact packing (None: none)."""
    region = start_region(tube)
    if n_robots < 1 or n_robots > _oler_bound(region):
        return None
    usable = region.room_m > 0.0
    inside = region.inside_box(region.center_m) & usable
    if window is not None:
        inside &= (region.l_m >= window[0]) & (region.l_m <= window[1])
    if not inside.any():
        return None
    low, high = float(region.l_m[inside].min()), float(region.l_m[inside].max())
    spacing = ROBOTARIUM.ic_spacing_m
    pairs = np.triu_indices(n_robots, 1)
    box = np.array(ROBOTARIUM.ic_box_m) - PACK_MARGIN_M
    rng = np.random.default_rng(0)

    def cost(z: FloatArray) -> tuple[float, FloatArray]:
        points, along, across = region.points(z[:n_robots], z[n_robots:])
        gap = points[:, None, :] - points[None, :, :]
        distance = np.maximum(np.hypot(gap[..., 0], gap[..., 1]), 1e-9) + np.eye(n_robots)  # none short of itself
        short = np.maximum(spacing + PACK_MARGIN_M - distance, 0.0)
        out = np.maximum(np.abs(points) - box, 0.0)
        grad = np.einsum('ij,ijk->ik', -2.0 * short / distance, gap) + 2.0 * out * np.sign(points)
        value = float(0.5 * np.sum(short**2) + np.sum(out**2))
        return value, np.concatenate([np.sum(grad * along, axis=1), np.sum(grad * across, axis=1)])

    bounds = [(low, high)] * n_robots + [(-1.0, 1.0)] * n_robots
    for _ in range(restarts):
        start = np.concatenate([rng.uniform(low, high, n_robots), rng.uniform(-1.0, 1.0, n_robots)])
        result = minimize(cost, start, jac=True, method='L-BFGS-B', bounds=bounds, options={'maxiter': 2000})
        l_m, across = result.x[:n_robots], result.x[n_robots:]
        points = tube.center_at(l_m) + (across * room_at(tube, l_m))[:, None] * tube.normal(l_m)  # exact, not tables
        gaps = np.hypot(*(points[:, None, :] - points[None, :, :]).transpose(2, 0, 1))[pairs]
        if (gaps.size == 0 or gaps.min() >= spacing) and region.inside_box(points).all():
            order = np.argsort(-l_m, kind='stable')  # front first
            return tuple(float(v) for v in l_m[order]), tuple((float(x), float(y)) for x, y in points[order])
    return None
