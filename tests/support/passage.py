"""A constructed passage's measures: every robot through, no collision, 3 robot-steps outside the tube; change any
field by keyword."""

from __future__ import annotations

from vtube_planning.swarm.metrics import PassageMetrics


def metrics(**change: object) -> PassageMetrics:
    values: dict[str, object] = {
        'passing_time_s': 12.5,
        'completed': True,
        'robots_passed': 8,
        'robots_counted': 8,
        'first_entry_s': 1.0,
        'last_exit_s': 13.5,
        'min_distance_m': 0.61234,
        'min_distance_time_s': 4.25,
        'collision_distance_m': 0.6,
        'collision_pairs': 0,
        'collision_steps': 0,
        'tube_violation_steps': 3,
        'robots_outside': 1,
        'max_outside_m': 0.0125,
        'speed_violations': 0,
        'speed_tracking_mean_mps': 0.1234,
        'speed_tracking_max_mps': 0.5,
        'density_tracking_mean_per_m2': 0.01234,
        'density_tracking_max_per_m2': 0.05,
    }
    return PassageMetrics(**(values | change))  # type: ignore[arg-type]
