"""Passage metrics of a constructed passage by hand; their JSON is strict; why a passage failed."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from tests.support.passage import metrics
from vtube_planning.swarm.metrics import passage_failures, passage_metrics


def test_metrics_of_a_constructed_passage() -> None:
    t = np.arange(0.0, 11.0)
    # two robots along a 10 m tube at 2 m/s, the second 1 m behind, 0.5 m apart laterally from t = 4 to 6
    l = np.stack([2.0 * t - 1.0, 2.0 * t - 2.0], axis=1)
    y = np.zeros_like(l)
    y[4:7, 1] = 0.5
    positions = np.stack([l, y], axis=1)  # (T, 2, N) along the x axis
    positions[4:7, 0, 1] = positions[4:7, 0, 0]  # abreast, 0.5 m apart: closer than 2 r_p = 0.6
    clearance = 1.0 - np.abs(y)
    clearance[3, 0] = -0.2  # robot 0 pokes out once, inside the span (l = 5 m)
    clearance[8, 0] = -0.5  # and once past the exit (l = 15 m), which does not count
    m = passage_metrics(t, positions, l, clearance, 10.0, collision_distance_m=0.6)
    assert m.completed and m.passing_time_s == pytest.approx(6.0 - 1.0)  # enters at t=1 (l=1), last exits t=6
    assert m.min_distance_m == pytest.approx(0.5) and m.min_distance_time_s == 4.0
    assert m.collision_pairs == 1 and m.collision_steps == 3
    assert m.tube_violation_steps == 1 and m.robots_outside == 1 and m.max_outside_m == pytest.approx(0.2)
    assert passage_metrics(t, positions, l, clearance, 10.0, collision_distance_m=0.4).collision_pairs == 0
    commands = np.stack([np.full((11, 2), 2.0), np.zeros((11, 2))], axis=1)  # speed 2 m/s
    assert (
        passage_metrics(
            t, positions, l, clearance, 10.0, collision_distance_m=0.6, speed_band_mps=(2.5, 5.0), commands_mps=commands
        ).speed_violations
        == 22
    )
    assert m.speed_violations is None and m.speed_tracking_mean_mps is None
    # with bodies of radius 0.05 m, clearances below 0.05 m count
    clearance[5, 1] = 0.03  # a body crossing the wall while its centre is inside
    bodies = passage_metrics(t, positions, l, clearance, 10.0, collision_distance_m=0.6, body_radius_m=0.05)
    centres = passage_metrics(t, positions, l, clearance, 10.0, collision_distance_m=0.6)
    assert bodies.tube_violation_steps == centres.tube_violation_steps + 1
    assert bodies.max_outside_m == pytest.approx(0.2 + 0.05)


def test_metrics_json_is_strict() -> None:
    t = np.arange(0.0, 4.0)
    l = np.stack([t, t - 0.5], axis=1)  # a 10 m tube that nobody leaves: no passing time
    positions = np.stack([l, np.zeros_like(l)], axis=1)
    m = passage_metrics(t, positions, l, np.ones_like(l), 10.0, collision_distance_m=0.6)
    assert math.isnan(m.passing_time_s) and not m.completed
    text = json.dumps(m.to_json(), allow_nan=False)  # would raise on NaN
    assert json.loads(text)['passing_time_s'] is None and json.loads(text)['min_distance_m'] == 0.5


def test_a_passage_fails_on_a_robot_that_never_exited_or_on_collisions_each_alone() -> None:
    assert passage_failures(metrics()) == ()  # tube violations are the caller's to judge
    lost = metrics(completed=False, robots_passed=5, passing_time_s=math.nan)
    assert passage_failures(lost) == ('3 of 8 robots never passed the exit (no passing time)',)
    crashed = metrics(collision_pairs=2, collision_steps=7, min_distance_m=0.3)
    assert passage_failures(crashed) == (
        '2 robot pairs collided (closer than 0.6 m, 7 steps; closest 0.300 m at t = 4.25 s)',
    )
    assert len(passage_failures(metrics(completed=False, robots_passed=7, collision_pairs=1))) == 2


def test_the_failures_of_a_measured_passage() -> None:
    """Two robots on a 10 m tube drive together at 2 m/s (the same positions at t = 0, 1, 2 s); the second stops at
    l = 4 m, the first drives through."""
    t = np.arange(0.0, 8.0)
    l = np.stack([2.0 * t, np.minimum(2.0 * t, 4.0)], axis=1)
    positions = np.stack([l, np.zeros_like(l)], axis=1)
    m = passage_metrics(t, positions, l, np.ones_like(l), 10.0, collision_distance_m=0.6)
    assert passage_failures(m) == (
        '1 of 2 robots never passed the exit (no passing time)',
        '1 robot pairs collided (closer than 0.6 m, 3 steps; closest 0.000 m at t = 0.00 s)',
    )
