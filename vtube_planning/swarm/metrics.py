"""Metrics of a swarm passing through a tube, from any trajectory (simulated, testbed or motion capture).

Inputs are arrays over time steps and robots: time stamps (T,), positions (T, 2, N), and what the tube says of
them (arc length and clearance, (T, N)). Everything returned is a plain float, int or bool, ready for JSON.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from vtube_planning.params import SwarmParams
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


def swarm_metrics(
    t_s: FloatArray,
    positions_m: FloatArray,
    l_m: FloatArray,
    clearance_m: FloatArray,
    length_m: float,
    swarm: SwarmParams,
    *,
    commands_mps: FloatArray | None = None,
    forward_speed_mps: FloatArray | None = None,
    density_per_m2: FloatArray | None = None,
    plan: Plan | None = None,
) -> dict[str, Any]:
    """The paper's measures of a passage, and tracking errors against a plan when one is given.

    Parameters
    ----------
    t_s, positions_m, l_m, clearance_m
        Time (T,), positions (T, 2, N), arc lengths and clearances lambda - |y| (T, N).
    commands_mps
        Commanded velocities (T, 2, N): their speeds are checked against [v_min, v_max].
    forward_speed_mps, density_per_m2
        Each robot's speed along the tube (T, N) and the measured density (T,), for tracking errors.
    plan
        The plan tracked (speed and density along the swarm centre's arc length).

    Returns
    -------
    dict
        ``passing_time_s`` (first robot enters to last robot exits; NaN if some robot never exits),
        ``completed``, ``min_distance_m`` and ``min_distance_time_s``, ``collision_pairs`` (distinct pairs closer
        than 2 r_p) and ``collision_steps``, ``tube_violation_steps`` (robot-steps outside the tube while
        0 <= l <= L), ``robots_outside``, ``max_outside_m``, ``speed_violations`` and, with a plan, the mean and
        largest speed and density tracking errors over the steps with the swarm's centre inside the tube.
    """
    entry = crossing_times(t_s, l_m, 0.0)
    exits = crossing_times(t_s, l_m, length_m)
    completed = bool(np.all(np.isfinite(exits)))
    passing = float(np.nanmax(exits) - np.nanmin(entry)) if completed and np.isfinite(entry).any() else float('nan')
    min_dist = min_distance_over_time(positions_m)
    k_min = int(np.argmin(min_dist))
    collision_radius = 2.0 * swarm.r_p_m
    pairs = close_pairs(positions_m, collision_radius) if positions_m.shape[2] > 1 else set()
    in_span = (l_m >= 0.0) & (l_m <= length_m)
    outside = in_span & (clearance_m < 0.0)
    metrics: dict[str, Any] = {
        'passing_time_s': passing,
        'completed': completed,
        'first_entry_s': float(np.nanmin(entry)) if np.isfinite(entry).any() else float('nan'),
        'last_exit_s': float(np.nanmax(exits)) if completed else float('nan'),
        'min_distance_m': float(min_dist[k_min]),
        'min_distance_time_s': float(t_s[k_min]),
        'collision_radius_m': collision_radius,
        'collision_pairs': len(pairs),
        'collision_steps': int(np.sum(min_dist < collision_radius)),
        'tube_violation_steps': int(outside.sum()),
        'robots_outside': int(outside.any(axis=0).sum()),
        'max_outside_m': float(max(0.0, -clearance_m[in_span].min())) if in_span.any() else 0.0,
    }
    if commands_mps is not None:
        speed = np.hypot(commands_mps[:, 0], commands_mps[:, 1])
        low = speed < swarm.v_min_mps - SPEED_TOLERANCE
        high = speed > swarm.v_max_mps + SPEED_TOLERANCE
        metrics['speed_violations'] = int(np.sum(low | high))
    if plan is not None and forward_speed_mps is not None and density_per_m2 is not None:
        center = l_m.mean(axis=1)
        inside = (center >= 0.0) & (center <= length_m)
        if inside.any():
            speed_err = np.abs(forward_speed_mps.mean(axis=1) - plan.speed(center))[inside]
            density_err = np.abs(density_per_m2 - plan.density(center))[inside]
            metrics.update({
                'speed_tracking_mean_mps': float(speed_err.mean()),
                'speed_tracking_max_mps': float(speed_err.max()),
                'density_tracking_mean_per_m2': float(density_err.mean()),
                'density_tracking_max_per_m2': float(density_err.max()),
            })
    return metrics
