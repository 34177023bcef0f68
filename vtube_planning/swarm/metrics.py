"""Metrics of a swarm passing through a tube, from any trajectory (simulated, testbed or motion capture).

Inputs are arrays over time steps and robots: time stamps (T,), positions (T, 2, N), and what the tube says of
them (arc length and clearance, (T, N)). The result is a frozen
[`PassageMetrics`][vtube_planning.swarm.metrics.PassageMetrics]; ``to_json()`` gives strict JSON (no NaN, no Infinity).
The collision distance and the speed band are given explicitly, so that recorded data can be measured with the
testbed's numbers rather than the swarm model's.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from vtube_planning.onboard import PlanProfile
from vtube_planning.planning.plan import Plan

FloatArray = NDArray[np.float64]

SPEED_TOLERANCE = 1e-9
"""Commanded speeds may leave [v_min, v_max] by this much (m/s) before they count as violations."""


def min_distance_over_time(positions_m: FloatArray) -> FloatArray:
    """Smallest distance between any two robots at every step, (T,) (inf with fewer than two robots)."""
    steps, _, n = positions_m.shape
    if n < 2:
        return np.full(steps, np.inf)
    out = np.empty(steps)
    for k in range(steps):
        dist, _ = cKDTree(positions_m[k].T).query(positions_m[k].T, k=2)
        out[k] = dist[:, 1].min()
    return out


def close_pairs(positions_m: FloatArray, radius_m: float) -> set[tuple[int, int]]:
    """Distinct robot pairs (i < j) that came closer than ``radius_m`` at any step."""
    found: set[tuple[int, int]] = set()
    for frame in positions_m:
        found.update(map(tuple, cKDTree(frame.T).query_pairs(radius_m, output_type='ndarray').tolist()))
    return found


def crossing_times(t_s: FloatArray, l_m: FloatArray, at_m: float) -> FloatArray:
    """First time each robot's arc length reaches ``at_m``, (N,), NaN if it never does."""
    reached = l_m >= at_m
    first = np.argmax(reached, axis=0)
    return np.where(reached.any(axis=0), t_s[first], np.nan)


def tube_violations(
    l_m: FloatArray,
    clearance_m: FloatArray,
    length_m: float,
    body_radius_m: float = 0.0,
    counted: NDArray[np.bool_] | None = None,
) -> tuple[int, int, float]:
    """Robot-steps outside the tube while 0 <= l <= L (clearance below ``body_radius_m``), the robots that ever
    were, and how far out at most (0 when none was), over the ``counted`` robots; NaN entries (no position) count
    as neither inside nor outside."""
    in_span = (l_m >= 0.0) & (l_m <= length_m)
    if counted is not None:
        in_span &= counted
    outside = in_span & (clearance_m < body_radius_m)
    deepest = float(max(0.0, body_radius_m - clearance_m[in_span].min())) if in_span.any() else 0.0
    return int(outside.sum()), int(outside.any(axis=0).sum()), deepest


@dataclass(frozen=True)
class PassageMetrics:
    """The paper's measures of a passage through a tube, and tracking errors against a plan.

    Attributes
    ----------
    passing_time_s
        First robot enters (l = 0) to last robot exits (l = L); NaN if some robot never exits. Robots that fail
        (a simulated fault) do not count here, in ``completed`` nor in the tube violations.
    completed
        Every (counted) robot exited.
    robots_passed, robots_counted
        How many of the counted robots exited, and how many were counted (the swarm, less a failed robot).
    first_entry_s, last_exit_s
        When the first robot entered and the last one exited (NaN when it did not happen).
    min_distance_m, min_distance_time_s
        The smallest distance between two robots, and when.
    collision_distance_m
        Robots closer than this collide (2 r_p in the paper).
    collision_pairs, collision_steps
        Distinct pairs that ever collided; steps with at least one collision.
    tube_violation_steps, robots_outside, max_outside_m
        Robot-steps outside the tube while 0 <= l <= L (the body, given a body radius; else the centre); robots
        that ever were; how far out at most.
    speed_violations
        Commands whose speed left the speed band (None when no commands or band were given).
    speed_tracking_mean_mps, speed_tracking_max_mps, density_tracking_mean_per_m2, density_tracking_max_per_m2
        |mean forward speed - v*(l_c)| and |density - rho*(l_c)| at the swarm centre's arc length l_c, over the
        steps with the centre inside the tube (None without a plan).
    """

    passing_time_s: float
    completed: bool
    robots_passed: int
    robots_counted: int
    first_entry_s: float
    last_exit_s: float
    min_distance_m: float
    min_distance_time_s: float
    collision_distance_m: float
    collision_pairs: int
    collision_steps: int
    tube_violation_steps: int
    robots_outside: int
    max_outside_m: float
    speed_violations: int | None = None
    speed_tracking_mean_mps: float | None = None
    speed_tracking_max_mps: float | None = None
    density_tracking_mean_per_m2: float | None = None
    density_tracking_max_per_m2: float | None = None

    def to_json(self) -> dict[str, Any]:
        """The measures as strict JSON values: NaN and infinities become None."""
        json_ready: dict[str, Any] = strict_json(asdict(self))
        return json_ready


def passage_failures(metrics: PassageMetrics) -> tuple[str, ...]:
    """Why a passage failed, one reason each: a counted robot that never exited, robots that collided (closer
    than the collision distance); empty when neither happened. Tube violations are judged by the caller, who
    knows whether they were measured on the bodies or on the centres."""
    failures = []
    if not metrics.completed:
        failures.append(
            f'{metrics.robots_counted - metrics.robots_passed} of {metrics.robots_counted} robots never passed the '
            'exit (no passing time)'
        )
    if metrics.collision_pairs:
        failures.append(
            f'{metrics.collision_pairs} robot pairs collided (closer than {metrics.collision_distance_m:g} m, '
            f'{metrics.collision_steps} steps; closest {metrics.min_distance_m:.3f} m at t = '
            f'{metrics.min_distance_time_s:.2f} s)'
        )
    return tuple(failures)


def strict_json(value: Any) -> Any:
    """``value`` with numpy scalars as Python numbers and NaN or infinite floats as None, recursively."""
    if isinstance(value, dict):
        return {str(k): strict_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [strict_json(v) for v in value]
    if isinstance(value, np.ndarray):
        return strict_json(value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    return value


def tracking_errors(
    l_m: FloatArray,
    forward_speed_mps: FloatArray,
    density_per_m2: FloatArray,
    plan: Plan | PlanProfile,
    length_m: float,
) -> dict[str, float]:
    """|mean forward speed - v*(l_c)| and |density - rho*(l_c)| at the swarm centre's arc length l_c: mean and
    max over the steps with the centre inside the tube (empty when it never is). Arrays as in passage_metrics."""
    center = l_m.mean(axis=1)
    inside = (center >= 0.0) & (center <= length_m)
    if not inside.any():
        return {}
    speed_err = np.abs(forward_speed_mps.mean(axis=1) - plan.speed(center))[inside]
    density_err = np.abs(density_per_m2 - plan.density(center))[inside]
    return {
        'speed_tracking_mean_mps': float(speed_err.mean()),
        'speed_tracking_max_mps': float(speed_err.max()),
        'density_tracking_mean_per_m2': float(density_err.mean()),
        'density_tracking_max_per_m2': float(density_err.max()),
    }


def passage_metrics(
    t_s: FloatArray,
    positions_m: FloatArray,
    l_m: FloatArray,
    clearance_m: FloatArray,
    length_m: float,
    *,
    collision_distance_m: float,
    body_radius_m: float = 0.0,
    speed_band_mps: tuple[float, float] | None = None,
    commands_mps: FloatArray | None = None,
    forward_speed_mps: FloatArray | None = None,
    density_per_m2: FloatArray | None = None,
    plan: Plan | PlanProfile | None = None,
    counted: NDArray[np.bool_] | None = None,
) -> PassageMetrics:
    """The measures of a passage (see [`PassageMetrics`][vtube_planning.swarm.metrics.PassageMetrics]).

    Parameters
    ----------
    t_s, positions_m, l_m, clearance_m, length_m
        Time (T,), positions (T, 2, N), arc lengths and clearances lambda - |y| (T, N), the tube's length L.
    collision_distance_m
        Centre distance below which two robots collide.
    body_radius_m
        A robot is outside the tube once its body is: when its centre's clearance is below this (0: the centre).
    speed_band_mps, commands_mps
        [v_min, v_max] and the commanded velocities (T, 2, N), whose speeds are checked against the band.
    forward_speed_mps, density_per_m2, plan
        Each robot's speed along the tube (T, N), the measured density (T,) and the plan (as flown) they track.
    counted
        The robots (N,) whose passage counts (entry, exit, completion, tube violations); None: all. Distances and
        collisions count every robot.
    """
    counted = np.ones(l_m.shape[1], dtype=bool) if counted is None else counted
    passing_time, completed, passed, first_entry, last_exit = passage_times(t_s, l_m[:, counted], length_m)
    min_dist = min_distance_over_time(positions_m)
    k_min = int(np.argmin(min_dist))
    violation_steps, robots_outside, max_outside = tube_violations(l_m, clearance_m, length_m, body_radius_m, counted)
    tracking: dict[str, float] = {}
    if plan is not None and forward_speed_mps is not None and density_per_m2 is not None:
        tracking = tracking_errors(l_m, forward_speed_mps, density_per_m2, plan, length_m)
    return PassageMetrics(
        passing_time_s=passing_time,
        completed=completed,
        robots_passed=passed,
        robots_counted=int(counted.sum()),
        first_entry_s=first_entry,
        last_exit_s=last_exit,
        min_distance_m=float(min_dist[k_min]),
        min_distance_time_s=float(t_s[k_min]),
        collision_distance_m=float(collision_distance_m),
        collision_pairs=len(close_pairs(positions_m, collision_distance_m)) if positions_m.shape[2] > 1 else 0,
        collision_steps=int(np.sum(min_dist < collision_distance_m)),
        tube_violation_steps=violation_steps,
        robots_outside=robots_outside,
        max_outside_m=max_outside,
        speed_violations=_speeding(commands_mps, speed_band_mps),
        **tracking,
    )


def passage_times(t_s: FloatArray, l_m: FloatArray, length_m: float) -> tuple[float, bool, int, float, float]:
    """The passing time, whether every robot of ``l_m`` (T, N) exited, how many did, the first entry and the last
    exit (NaN where they did not happen)."""
    entry = crossing_times(t_s, l_m, 0.0)
    exits = crossing_times(t_s, l_m, length_m)
    completed = bool(np.all(np.isfinite(exits)))
    entered = bool(np.isfinite(entry).any())
    return (
        float(np.nanmax(exits) - np.nanmin(entry)) if completed and entered else math.nan,
        completed,
        int(np.isfinite(exits).sum()),
        float(np.nanmin(entry)) if entered else math.nan,
        float(np.nanmax(exits)) if completed else math.nan,
    )


def _speeding(commands_mps: FloatArray | None, speed_band_mps: tuple[float, float] | None) -> int | None:
    """Commands (T, 2, N) whose speed leaves the band [v_min, v_max] by more than ``SPEED_TOLERANCE`` (None without
    commands or band)."""
    if commands_mps is None or speed_band_mps is None:
        return None
    speed = np.hypot(commands_mps[:, 0], commands_mps[:, 1])
    low, high = speed_band_mps
    return int(np.sum((speed < low - SPEED_TOLERANCE) | (speed > high + SPEED_TOLERANCE)))
