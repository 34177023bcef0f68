"""The safety filter of the tube experiment: the barrier certificate's rows and the speed band in one QP.

The barrier rows are the Robotarium certificates' (:mod:`robotarium_exp.rps.utilities.barrier_rows`).
:class:`SafetyFilter` adds, for every robot still flying the tube, the speed band of a speed-constrained unicycle as
linear rows in its control point's velocity u: the near-identity map gives the forward speed ``v = e_theta . u`` and
the turn rate ``omega = e_theta_perp . u / d`` exactly, so ``v_min <= e_theta . u <= v_max`` and
``|e_theta_perp . u| <= lateral_max`` are linear. ``lateral_max`` is what the wheels allow at v_max
(``v_max + (L/2) omega_max = r phi_max``), so every command the filter returns is realised without wheel
saturation. Parked robots (past the exit) keep only the wheel limit. When the barrier rows and the band cannot hold
together, safety wins: the band is dropped for that step (and counted), the robots get the barrier's velocity
through the exact map.

Robots flying the tube (and past its exit until they leave for a slot) also get a row for the nearer wall or its
extension: ``o . u <= WALL_GAIN_PER_S (c - WALL_KEEP_M)`` for the control point's clearance c = lambda(l) - |y| and
o minus c's gradient (outward across the tube, and backwards where the tube narrows: flying on along a narrowing
closes in on a robot), a barrier that keeps the body off the wall's line; parked robots get one for the exit line
behind them (:data:`EXIT_KEEP_M`), so that robots still leaving do not push them back beside the tube (the curve,
six robots without initialization: 49 robot-steps, 0.16 m over, without it). The law's own keeping push is capped
with the rest of its steering at v* - v_min (0.04 m/s at the plan's slowest), and the barrier rows between robots do
not know the walls: in a crowd entering a narrowing they pushed bodies over the walls (the trapezoid at N = 8
without initialization: 104 robot-steps). Where the rows cannot all hold, the band goes first and the wall rows
stay, so that a robot may slow below v_min to keep off a wall; they go too only when the robots cannot keep apart
with them (the twenty-robot curve under the testbed model `fitted`, seeds 8 and 9: a body up to 7 cm over the wall
while the band was dropped with the walls).

The QP ``min ||u - u_hat||^2 subject to A u <= b`` is a least-distance problem, solved exactly through
non-negative least squares (Lawson and Hanson, *Solving Least Squares Problems*, ch. 23) with scipy's ``nnls``:
numpy and scipy only, so :mod:`submission.builder` inlines this module and the testbed flies the same filter.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import nnls

from robotarium_exp.rps.utilities.barrier_rows import BarrierSpec, barrier_rows

FloatArray = NDArray[np.float64]

FEASIBILITY_TOL = 1e-9
"""Largest violation (relative to a row's scale) of a returned solution's rows."""
WALL_KEEP_M = 0.09
"""The control point's clearance the wall rows keep: the body's radius (0.055 m) and 0.035 m for the body's centre
trailing the control point by d at an angle to the wall."""
EXIT_KEEP_M = 0.05
"""How far beyond the exit line a parked robot's control point stays: d, so that its body's centre does not come
back beside the tube (the nearest slots lie 0.08 m beyond)."""
WALL_GAIN_PER_S = 1.0
"""How fast a control point may approach a wall per metre of room above what the rows keep (1/s)."""


def least_distance_nnls(u_hat: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray | None:
    """argmin ||u - u_hat||^2 subject to a u <= b, exactly (via NNLS); None if the rows cannot hold together."""
    slack = b - a @ u_hat
    if a.shape[0] == 0 or np.all(slack >= 0.0):
        unchanged: FloatArray = u_hat.copy()
        return unchanged
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
    u: FloatArray = u_hat + z
    return u


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
        self,
        u_hat: FloatArray,
        poses: FloatArray,
        points: FloatArray,
        flying: NDArray[np.bool_],
        walls: tuple[FloatArray, FloatArray] | None = None,
    ) -> tuple[FloatArray, bool]:
        """Filtered control-point velocities (2, N), and whether the band held for the flying robots.

        ``walls``: the outward normal towards each robot's wall (2, N) and the room above what the row keeps (N,),
        NaN for a robot without one (no row; :func:`robotarium_exp.flight.walls`); None: no wall rows.
        """
        n = u_hat.shape[1]
        a_safe, b_safe = barrier_rows(points, self.barrier)
        a_band, b_band = self._band_rows(poses, flying)
        a_wall, b_wall = self._wall_rows(*walls) if walls is not None else (np.zeros((0, 2 * n)), np.zeros(0))
        a_wheel, b_wheel = self._wheel_rows(poses, ~flying)
        flat = u_hat.reshape(-1, order='F')
        self.stats.solves += 1
        u = least_distance_nnls(
            flat, np.vstack([a_safe, a_band, a_wall, a_wheel]), np.concatenate([b_safe, b_band, b_wall, b_wheel])
        )
        held = u is not None
        if u is None:  # safety wins: the band goes, every robot keeps its wheel limits, the walls while they can
            self.stats.band_dropped += 1
            a_all, b_all = self._wheel_rows(poses, np.ones(n, dtype=bool))
            u = least_distance_nnls(flat, np.vstack([a_safe, a_wall, a_all]), np.concatenate([b_safe, b_wall, b_all]))
            if u is None:
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

    @staticmethod
    def _wall_rows(outward: FloatArray, room: FloatArray) -> tuple[FloatArray, FloatArray]:
        """o . u <= WALL_GAIN_PER_S h for the robots with a wall (a finite room h)."""
        k = np.flatnonzero(np.isfinite(room))
        a = np.zeros((k.size, 2 * outward.shape[1]))
        a[np.arange(k.size), 2 * k], a[np.arange(k.size), 2 * k + 1] = outward[0, k], outward[1, k]
        return a, WALL_GAIN_PER_S * room[k]

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
