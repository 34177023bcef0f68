"""The verifier's counts: from a simulator's counters of either generation, and recounted from poses and commands,
checked against counts worked out by hand and by an independent loop."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.spec import ROBOTARIUM
from robotarium_exp.verifier import SIMULATOR_NAMES, VerifierCounts, closest_centres_m, recount, restart_shared_counters


def test_counts_from_either_generation_s_counters() -> None:
    v2 = {'robots_too_close': 3, 'robots_outside_boundaries': 1, 'exceeded_actuator_limits': np.int64(2)}
    assert VerifierCounts.from_simulator(v2) == VerifierCounts(3, 1, 2)
    classic = {'collision': 4, 'boundary': 5, 'actuator': 0, 'collision_string': 'robots too close'}
    assert VerifierCounts.from_simulator(classic) == VerifierCounts(4, 5, 0)
    assert VerifierCounts.from_simulator({}) == VerifierCounts() and VerifierCounts().clean
    counts = VerifierCounts(3, 1, 2)
    assert not counts.clean
    assert counts.to_json() == {'robots_too_close': 3, 'robots_outside_boundaries': 1, 'exceeded_actuator_limits': 2}
    assert VerifierCounts.from_simulator(counts.to_json()) == counts
    assert counts.describe() == ('3 pair-steps too close, 1 steps outside the arena, 2 steps over the actuator limit')
    assert set(SIMULATOR_NAMES) == {'too_close', 'outside', 'actuator'}


def test_recount_by_hand() -> None:
    """Three robots, three steps: a pair too close (shifted centres), one outside, one wheel over the limit."""
    d = ROBOTARIUM.collision_diameter_m
    poses = np.zeros((3, 3, 3))
    poses[:, 0] = [[0.0, 1.0, -1.0]] * 3
    poses[0, 0, 1] = 0.0 + d + 2 * ROBOTARIUM.collision_offset_m - 1e-6  # facing each other: shifted gap < d
    poses[0, 2, 1] = np.pi  # robot 1 faces robot 0
    poses[1, 0, 2] = -1.7  # robot 2 outside at step 1
    velocities = np.zeros((3, 2, 3))
    velocities[2, 0, 0] = 0.21  # over 0.2 m/s on both wheels at step 2
    assert recount(poses, velocities) == VerifierCounts(too_close=1, outside=1, actuator=1)
    assert recount(poses[:, :, :1], velocities[:, :, :1]) == VerifierCounts(0, 0, 1)  # one robot: no pairs


def test_recount_equals_an_independent_loop_on_random_runs() -> None:
    rng = np.random.default_rng(4)
    s = ROBOTARIUM
    poses = np.stack([rng.uniform(-1.8, 1.8, (20, 5)), rng.uniform(-1.2, 1.2, (20, 5)), rng.uniform(-4, 4, (20, 5))], 1)
    velocities = np.stack([rng.uniform(-0.12, 0.12, (20, 5)), rng.uniform(-1, 1, (20, 5))], 1)
    velocities[:10] *= 1.5  # within the limit in the second half, over it in some steps of the first
    close = outside = actuator = 0
    for p, u in zip(poses, velocities, strict=True):
        outside += any(not (-1.6 <= x <= 1.6 and -1.0 <= y <= 1.0) for x, y in p[:2].T)
        c = p[:2] + s.collision_offset_m * np.array([np.cos(p[2]), np.sin(p[2])])
        close += sum(
            np.hypot(*(c[:, i] - c[:, j])) <= s.collision_diameter_m for i in range(5) for j in range(i + 1, 5)
        )
        left = (u[0] - 0.5 * s.base_length_m * u[1]) / s.wheel_radius_m
        right = (u[0] + 0.5 * s.base_length_m * u[1]) / s.wheel_radius_m
        actuator += bool(np.any(np.abs(np.concatenate([left, right])) > s.max_wheel_speed_radps))
    assert recount(poses, velocities) == VerifierCounts(close, outside, actuator)
    assert 0 < outside < 20 and 0 < actuator < 20


def test_closest_centres() -> None:
    poses = np.zeros((2, 3, 3))
    poses[:, 0] = [[0.0, 0.3, 1.0], [0.0, 0.5, 0.6]]
    assert closest_centres_m(poses) == pytest.approx(0.1, abs=1e-15)
    assert closest_centres_m(poses[:, :, :1]) == float('inf') and closest_centres_m(poses[:0]) == float('inf')


class SharedCounters:
    """As PyPI's simulator: errors counted into a mutable default argument, one dict for every instance."""

    def _validate(self, errors: dict = {}) -> dict:  # noqa: B006 -- the shared default is the point
        errors['actuator'] = errors.get('actuator', 0) + 1
        return errors


class OwnCounters:
    def __init__(self) -> None:
        self.errors = {'actuator': 2}

    def _validate(self, errors: dict | None = None) -> dict:
        return self.errors


def test_a_run_starts_the_shared_counters_from_zero_and_leaves_its_own_alone() -> None:
    first = SharedCounters()
    first._validate()
    first._validate()
    second = SharedCounters()
    restart_shared_counters(second)
    assert VerifierCounts.from_simulator(second._validate()).actuator == 1  # this run's step only
    own = OwnCounters()
    restart_shared_counters(own)
    assert own.errors == {'actuator': 2}
