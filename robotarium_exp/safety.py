"""Safety filters of the tube experiment: the barrier certificate's rows, and one QP that also keeps the speed band.

The pairwise barrier rows ``-2 (x_i - x_j)^T (u_i - u_j) <= gamma h_ij^3``, ``h_ij = ||x_i - x_j||^2 - R^2``, the
boundary rows ``+/- u <= 0.4 gamma (distance to the wall - R/2)^3`` and the V2 speed polygon are those of the
Robotarium's certificates (:mod:`robotarium_exp.rps.utilities.barrier_certificates` builds its certificates on
:func:`barrier_rows`).

The tube experiment's :class:`SafetyFilter` adds, for every robot still flying the tube, the speed band of a
speed-constrained unicycle as linear rows in its control point's velocity u: the near-identity map gives the
forward speed ``v = e_theta . u`` and the turn rate ``omega = e_theta_perp . u / d`` exactly, so
``v_min <= e_theta . u <= v_max`` and ``|e_theta_perp . u| <= lateral_max`` are linear. ``lateral_max`` is what the
wheels allow at v_max (``v_max + (L/2) omega_max = r phi_max``), so every command the filter returns is realised
without wheel saturation. Parked robots (past the exit) keep only the wheel limit. When the barrier rows and the
band cannot hold together, safety wins: the band is dropped for that step (and counted), the robots get the
barrier's velocity through the exact map.

The QP ``min ||u - u_hat||^2 subject to A u <= b`` is a least-distance problem, solved exactly through
non-negative least squares (Lawson and Hanson, *Solving Least Squares Problems*, ch. 23) with scipy's ``nnls``:
numpy and scipy only, so :mod:`submission.builder` inlines this module and the testbed flies the same filter.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import nnls

FloatArray = NDArray[np.float64]

POLYGON_SIDES = 8
FEASIBILITY_TOL = 1e-9
"""Largest violation (relative to a row's scale) of a returned solution's rows."""


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
        bounds.append(np.concatenate([walls[1, n:], walls[0, n:], walls[1, :n], walls[0, :n]]))
    if spec.speed_polygon:
        blocks.append(layout.polygon_rows)
        bounds.append(layout.polygon_bounds.ravel())
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
        return self.lower.size - self.a.shape[0]

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
    return (pairs[:, :, None] * (-2.0 * diff.T[:, None, :])).reshape(p, 2 * n)


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
    for side in range(POLYGON_SIDES):
        angle = 2 * math.pi * side / POLYGON_SIDES
        sides[side, robots, 2 * robots] = math.cos(angle)
        sides[side, robots, 2 * robots + 1] = math.sin(angle)
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
        walls.reshape(4 * n, 2 * n),
        sides.reshape(-1, 2 * n),
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


def least_distance_nnls(u_hat: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray | None:
    """argmin ||u - u_hat||^2 subject to a u <= b, exactly (via NNLS); None if the rows cannot hold together."""
    slack = b - a @ u_hat
    if a.shape[0] == 0 or np.all(slack >= 0.0):
        return u_hat.copy()
    scale = np.maximum(np.abs(a).max(axis=1), 1e-300)  # unit rows: the right sides span many orders of magnitude
    rows, room = a / scale[:, None], slack / scale
    # least distance: min ||z|| with rows z <= room, i.e. G z >= h for G = -rows, h = -room
    e = np.vstack([-rows.T, -room[None, :]])
    f = np.zeros(e.shape[0])
    f[-1] = 1.0
    w, _ = nnls(e, f, maxiter=50 * e.shape[1])
    residual = e @ w - f
    if abs(residual[-1]) < 1e-12:
        return None
    z = -residual[:-1] / residual[-1]
    if np.max(rows @ z - room) > FEASIBILITY_TOL:
        return None
    return u_hat + z


@dataclass
class FilterStats:
    """Counters of a safety filter over a run."""

    solves: int = 0
    band_dropped: int = 0
    failures: int = 0
    intervention_mps: float = 0.0
    """Sum over steps of the total change of the commands, sum_i ||u_i - u_hat_i|| (m/s)."""
    messages: list[str] = field(default_factory=list)


class SafetyFilter:
    """Barrier certificate with the arena boundary, the speed band of flying robots and the wheel limits.

    Parameters
    ----------
    barrier
        Safety radius, gain and arena of the barrier rows (``magnitude_limit`` is not used: the band and the
        wheel rows bound the speed).
    v_min_mps, v_max_mps
        The speed band of a robot flying the tube.
    projection_distance_m, base_length_m, wheel_speed_mps
        d of the near-identity map, the axle length and the largest wheel rim speed r phi_max.
    """

    def __init__(
        self,
        barrier: BarrierSpec,
        v_min_mps: float,
        v_max_mps: float,
        projection_distance_m: float,
        base_length_m: float,
        wheel_speed_mps: float,
    ) -> None:
        self.barrier = barrier
        self.v_min, self.v_max = float(v_min_mps), float(v_max_mps)
        self.d = float(projection_distance_m)
        self.half_base = 0.5 * float(base_length_m)
        self.wheel = float(wheel_speed_mps)
        self.lateral_max = (self.wheel - self.v_max) * self.d / self.half_base
        self.stats = FilterStats()

    def __call__(
        self, u_hat: FloatArray, poses: FloatArray, points: FloatArray, flying: NDArray[np.bool_]
    ) -> tuple[FloatArray, bool]:
        """Filtered control-point velocities (2, N), and whether the band held for the flying robots."""
        n = u_hat.shape[1]
        a_safe, b_safe = barrier_rows(points, self.barrier)
        a_band, b_band = self._band_rows(poses, flying)
        a_wheel, b_wheel = self._wheel_rows(poses, ~flying)
        flat = u_hat.reshape(-1, order='F')
        self.stats.solves += 1
        u = least_distance_nnls(flat, np.vstack([a_safe, a_band, a_wheel]), np.concatenate([b_safe, b_band, b_wheel]))
        held = u is not None
        if u is None:  # safety wins: every robot keeps only its wheel limits
            self.stats.band_dropped += 1
            a_all, b_all = self._wheel_rows(poses, np.ones(n, dtype=bool))
            u = least_distance_nnls(flat, np.vstack([a_safe, a_all]), np.concatenate([b_safe, b_all]))
        if u is None:
            self.stats.failures += 1
            self.stats.messages.append(f'safety QP infeasible at solve {self.stats.solves}; holding the robots')
            u = np.zeros_like(flat)
        out = u.reshape(2, n, order='F')
        self.stats.intervention_mps += float(np.hypot(*(out - u_hat)).sum())
        return out, held

    def _frames(self, poses: FloatArray, robots: NDArray[np.bool_]) -> tuple[NDArray[np.intp], FloatArray, FloatArray]:
        k = np.flatnonzero(robots)
        return k, np.cos(poses[2, k]), np.sin(poses[2, k])

    def _band_rows(self, poses: FloatArray, flying: NDArray[np.bool_]) -> tuple[FloatArray, FloatArray]:
        """v_min <= e.u <= v_max and |e_perp.u| <= lateral_max for the flying robots."""
        k, c, s = self._frames(poses, flying)
        n, m = poses.shape[1], k.size
        a = np.zeros((4 * m, 2 * n))
        for block, (ex, ey, bound) in enumerate(
            (
                (c, s, self.v_max),
                (-c, -s, -self.v_min),
                (-s, c, self.lateral_max),
                (s, -c, self.lateral_max),
            )
        ):
            rows = block * m + np.arange(m)
            a[rows, 2 * k], a[rows, 2 * k + 1] = ex, ey
        b = np.repeat([self.v_max, -self.v_min, self.lateral_max, self.lateral_max], m)
        return a, b

    def _wheel_rows(self, poses: FloatArray, robots: NDArray[np.bool_]) -> tuple[FloatArray, FloatArray]:
        """|v| + (L/2) |omega| <= r phi_max, i.e. +/- e.u +/- (L / 2d) e_perp.u <= r phi_max."""
        k, c, s = self._frames(poses, robots)
        n, m = poses.shape[1], k.size
        ratio = self.half_base / self.d
        a = np.zeros((4 * m, 2 * n))
        for block, (sv, sw) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
            rows = block * m + np.arange(m)
            a[rows, 2 * k] = sv * c - sw * ratio * s
            a[rows, 2 * k + 1] = sv * s + sw * ratio * c
        return a, np.full(4 * m, self.wheel)
