"""The rows of the Robotarium's barrier certificates, as linear constraints on the robots' velocities (numpy only).

The pairwise barrier rows ``-2 (x_i - x_j)^T (u_i - u_j) <= gamma h_ij^3``, ``h_ij = ||x_i - x_j||^2 - R^2``, the
boundary rows ``+/- u <= 0.4 gamma (distance to the wall - R/2)^3`` and V2's speed polygon: the bundled certificates
(:mod:`robotarium_exp.rps.utilities.barrier_certificates`) and the tube experiment's safety filter
(:mod:`robotarium_exp.safety`) both build on them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property, lru_cache
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

POLYGON_SIDES = 8

_DIAGONAL = 1 / np.sqrt(2)
SIDE_NORMALS = (
    (1.0, 0.0),
    (_DIAGONAL, _DIAGONAL),
    (0.0, 1.0),
    (-_DIAGONAL, _DIAGONAL),
    (-1.0, 0.0),
    (-_DIAGONAL, -_DIAGONAL),
    (0.0, -1.0),
    (_DIAGONAL, -_DIAGONAL),
)
"""The speed polygon's outward normals, side by side from +x counter-clockwise, with V2's coefficients (exactly 0
and 1/sqrt(2), not cos and sin of the angle), so the testbed QP's matrix is V2's, coefficient for coefficient."""


@dataclass(frozen=True)
class BarrierSpec:
    """The QP's data: safety radius R, gain gamma, speed limit, boundary [xmin, xmax, ymin, ymax], polygon.

    ``full_first_side``: V2's plain certificates put the polygon's first side (+x) at the limit and the other
    seven at limit cos(pi/8); its boundary certificates put all eight at limit cos(pi/8).
    """

    safety_radius: float
    barrier_gain: float
    magnitude_limit: float
    boundary: tuple[float, float, float, float] | None
    speed_polygon: bool
    full_first_side: bool = True


def barrier_rows(x: FloatArray, spec: BarrierSpec) -> tuple[FloatArray, FloatArray]:
    """Every constraint row A u <= b (u stacked robot by robot: [u_0x, u_0y, u_1x, ...]) for positions x (2, N), in
    V2's order: the pairs i < j, then the four walls (+y, -y, +x, -x) and the polygon's sides, each robot by robot.
    """
    layout = _row_layout(x.shape[1], spec)
    diff, _, b_pair = _pair_terms(x, spec, layout)
    blocks, bounds = [_pair_rows(diff, layout.pairs)], [b_pair]
    if spec.boundary is not None:
        n, walls = x.shape[1], _wall_bounds(x, spec, layout)
        blocks.append(layout.wall_rows)
        bounds.append(np.stack([walls[1, n:], walls[0, n:], walls[1, :n], walls[0, :n]], axis=1).ravel())
    if spec.speed_polygon:
        blocks.append(layout.polygon_rows)
        bounds.append(layout.polygon_bounds.T.ravel())
    return np.concatenate(blocks), np.concatenate(bounds)


@dataclass(frozen=True, eq=False)
class BoundedRows:
    """The same constraints as two-sided rows ``lower <= C u <= upper``, ``C = [I; a]``, on u stacked component by
    component (``[u_0x, ..., u_(N-1)x, u_0y, ...]``, i.e. ``dxi.ravel()``): the first 2N rows bound u's own
    components (DAQP's simple bounds), the rows of ``a`` follow; ``keys`` name each row's constraint from call to call
    (ascending: the 2N components, then the polygon's diagonal sides, then the pairs i < j by their place).
    """

    a: FloatArray
    lower: FloatArray
    upper: FloatArray
    keys: NDArray[np.intp]

    @property
    def bounded(self) -> int:
        """How many of the rows bound u's components (the first ones)."""
        return int(self.lower.size - self.a.shape[0])

    @cached_property
    def norms(self) -> FloatArray:
        """Each row's norm."""
        return np.concatenate([np.ones(self.bounded), np.sqrt(np.square(self.a).sum(axis=1))])

    def apply(self, u: FloatArray) -> FloatArray:
        """C u."""
        return np.concatenate([u[: self.bounded], self.a @ u])


def bounded_barrier_rows(x: FloatArray, spec: BarrierSpec) -> BoundedRows:
    """:func:`barrier_rows` folded and pruned, the same feasible set: the walls and the polygon's sides along the
    axes bound u's components, each two opposite diagonal sides make one two-sided row, and (with the polygon) the
    pairs too far apart to bind are left out: ``|-2 e.(u_i - u_j)| <= 2 d 2 u_max / cos(pi/8) < gamma h^3``.
    """
    n = x.shape[1]
    layout = _row_layout(n, spec)
    diff, dist2, b_pair = _pair_terms(x, spec, layout)
    if spec.speed_polygon:
        reach = 4.0 * spec.magnitude_limit / math.cos(math.pi / POLYGON_SIDES)
        kept = (b_pair < reach * np.sqrt(dist2)).nonzero()[0]
        pairs, diff, b_pair = layout.pairs[kept], diff[:, kept], b_pair[kept]
    else:
        kept, pairs = np.arange(b_pair.size), layout.pairs
    diagonal, fixed = layout.diagonal_rows.shape[0], layout.fixed_keys.size
    a = np.empty((diagonal + kept.size, 2 * n))
    a[:diagonal] = layout.diagonal_rows
    np.multiply(pairs[:, None, :], -2.0 * diff.T[:, :, None], out=a[diagonal:].reshape(kept.size, 2, n))
    bounds = np.empty((2, fixed + kept.size))  # -lower, upper
    bounds[:, :fixed] = layout.fixed_bounds
    bounds[0, fixed:], bounds[1, fixed:] = np.inf, b_pair
    if spec.boundary is not None:
        np.minimum(bounds[:, : 2 * n], _wall_bounds(x, spec, layout), out=bounds[:, : 2 * n])
    return BoundedRows(a, -bounds[0], bounds[1], np.concatenate([layout.fixed_keys, fixed + kept]))


def _pair_terms(x: FloatArray, spec: BarrierSpec, layout: _Layout) -> tuple[FloatArray, FloatArray, FloatArray]:
    """x_i - x_j (2, pairs), its squared norm and the pair rows' right sides gamma h^3, h = ||x_i - x_j||^2 - R^2."""
    diff = x @ layout.pairs.T
    dist2 = np.square(diff).sum(axis=0)
    return diff, dist2, spec.barrier_gain * (dist2 - spec.safety_radius**2) ** 3


def _wall_bounds(x: FloatArray, spec: BarrierSpec, layout: _Layout) -> FloatArray:
    """The walls' bounds on u's components (2, 2N), component by component: 0.4 gamma (distance to the wall - R/2)^3
    to the low walls (-x, -y; bounds on -u) and to the high ones (+x, +y; bounds on u)."""
    room = layout.wall_offsets + layout.wall_signs * x.ravel()
    return 0.4 * spec.barrier_gain * room**3


def _pair_rows(diff: FloatArray, pairs: FloatArray) -> FloatArray:
    """The rows -2 (x_i - x_j)^T (u_i - u_j) (u robot by robot) of the pairs (rows of ``pairs``: +1 at i, -1 at j)
    with differences diff (2, pairs)."""
    p, n = pairs.shape
    rows: FloatArray = (pairs[:, :, None] * (-2.0 * diff.T[:, None, :])).reshape(p, 2 * n)
    return rows


class _Layout(NamedTuple):
    """What the rows of N robots share from call to call (:func:`_row_layout`)."""

    pairs: FloatArray
    """(N (N - 1) / 2, N): +1 at i and -1 at j for each pair i < j."""
    wall_rows: FloatArray
    polygon_rows: FloatArray
    polygon_bounds: FloatArray
    """(sides, N): side k's bound for each robot."""
    diagonal_rows: FloatArray
    fixed_bounds: FloatArray
    """(2, 2N + diagonal rows): -lower and upper of the components (the polygon's sides along the axes, inf
    without) and of the diagonal rows."""
    fixed_keys: NDArray[np.intp]
    """The keys of the components' bounds and the diagonal rows."""
    wall_offsets: FloatArray
    wall_signs: FloatArray
    """The walls as bounds on u's components: ``offset + sign x.ravel()`` (2, 2N) is the room to the low and the
    high wall (R/2 in): x - low, high - x."""


@lru_cache(maxsize=32)
def _row_layout(n: int, spec: BarrierSpec) -> _Layout:
    """The pairs, the walls' rows (+y, -y, +x, -x), the polygon's sides (V2: at limit cos(pi/8), the first one at the
    limit if ``full_first_side``), each robot by robot, and the same sides as :class:`BoundedRows` has them: sides
    0 and 4 (+x, -x) and 2 and 6 (+y, -y) bound the components, sides 1 and 5, 3 and 7 make two-sided rows.
    """
    i, j = np.triu_indices(n, k=1)
    pairs = np.zeros((i.size, n))
    pairs[np.arange(i.size), i], pairs[np.arange(i.size), j] = 1.0, -1.0
    robots = np.arange(n)
    walls = np.zeros((4, n, 2 * n))
    for block, (axis, sign) in enumerate(((1, 1.0), (1, -1.0), (0, 1.0), (0, -1.0))):
        walls[block, robots, 2 * robots + axis] = sign
    sides = np.zeros((POLYGON_SIDES, n, 2 * n))
    bounds = np.empty((POLYGON_SIDES, n))
    for side, (cos, sin) in enumerate(SIDE_NORMALS):
        sides[side, robots, 2 * robots] = cos
        sides[side, robots, 2 * robots + 1] = sin
        full = side == 0 and spec.full_first_side
        bounds[side] = spec.magnitude_limit * (1.0 if full else math.cos(math.pi / POLYGON_SIDES))
    if spec.speed_polygon:  # component by component: all x, then all y
        diagonal_rows = sides[[1, 3]][:, :, np.r_[0 : 2 * n : 2, 1 : 2 * n : 2]].reshape(2 * n, 2 * n)
        fixed_bounds = bounds[[4, 6, 5, 7, 0, 2, 1, 3]].reshape(2, 4 * n)
    else:
        diagonal_rows, fixed_bounds = np.zeros((0, 2 * n)), np.full((2, 2 * n), np.inf)
    xmin, xmax, ymin, ymax = spec.boundary or (-np.inf, np.inf, -np.inf, np.inf)
    half = spec.safety_radius / 2
    edges = np.repeat([[xmin + half, ymin + half], [xmax - half, ymax - half]], n, axis=1)
    layout = _Layout(
        pairs,
        walls.transpose(1, 0, 2).reshape(4 * n, 2 * n),  # robot by robot, as V2 lists them
        sides.transpose(1, 0, 2).reshape(-1, 2 * n),
        bounds,
        diagonal_rows,
        fixed_bounds,
        np.arange(fixed_bounds.shape[1]),
        edges * [[-1.0], [1.0]],
        np.array([[1.0], [-1.0]]),
    )
    for array in layout:
        array.flags.writeable = False  # shared by every call
    return layout
