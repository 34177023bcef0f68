"""The trajectory seen from the trapezoid's tube (straight along y = 0 from x = -1.45, 0.4 m wide at first), and
the passage as observed or from a recorded start, on hand-made cases."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.analysis.passage import (
    INFERRED_START,
    AlongTube,
    FlightStart,
    Passage,
    along_tube,
    observed_passage,
    recorded_passage,
)
from robotarium_exp.analysis.trajectory import Trajectory
from robotarium_exp.errors import AnalysisError

ENTRANCE_X = -1.45


def test_along_the_straight_part_by_hand(trapezoid) -> None:
    scene, _ = trapezoid
    half = float(scene.tube.half_width(0.0))
    assert float(scene.tube.half_width(1.2)) == pytest.approx(half)  # still straight and as wide at 1.2 m
    t = np.arange(6) * 0.5
    x = ENTRANCE_X + 0.5 + 0.08 * t[:, None] + np.array([0.0, 0.1, 0.25])  # l from 0.5 to 0.97
    y = np.broadcast_to(np.array([0.05, -0.1, 0.0]), x.shape)
    positions = np.stack([x, y], axis=1)
    positions[2, :, 1] = np.nan  # robot 1 missing in frame 2
    along = along_tube(Trajectory(t, positions, None, ('a', 'b', 'c')), scene)
    present = np.isfinite(positions[:, 0])
    np.testing.assert_allclose(along.l_m[present], (x - ENTRANCE_X)[present], atol=1e-9)
    np.testing.assert_allclose(along.clearance_m[present], (half - np.abs(y))[present], atol=1e-9)
    assert np.isnan(along.l_m[2, 1]) and np.isnan(along.forward_speed_mps[2, 1])
    np.testing.assert_allclose(along.forward_speed_mps[:, [0, 2]], 0.08, atol=1e-9)  # np.gradient of a line
    np.testing.assert_array_equal(along.complete, [True, True, False, True, True, True])
    r_a = scene.swarm.r_a_m
    length = (x.max(axis=1) - x.min(axis=1)) + 2 * r_a
    expected = 3 / (2 * half * length)  # n over the area of a straight strip
    np.testing.assert_allclose(along.density_per_m2[along.complete], expected[along.complete], rtol=1e-6)
    assert np.isnan(along.density_per_m2[2])


def along_of(l_m: np.ndarray, clearance: float = 0.1) -> AlongTube:
    t = np.arange(l_m.shape[0]) * 1.0
    nan = np.full_like(l_m, np.nan)
    return AlongTube(t, l_m, np.where(np.isnan(l_m), np.nan, clearance), nan, nan[:, 0], np.isfinite(l_m).all(1))


def test_a_whole_passage_is_timed_first_entry_to_last_exit() -> None:
    l_m = np.array([[-0.2, -0.5], [0.1, -0.1], [1.0, 0.5], [2.1, 1.5], [2.5, 2.0]])  # L = 2
    passage = observed_passage(along_of(l_m), 2.0, ('a', 'b'))
    assert passage == Passage(
        passing_time_s=4.0 - 1.0,
        first_entry_s=1.0,
        last_exit_s=4.0,
        entrance_observed=True,
        never_inside=(),
        not_exited=(),
        robots_passed=2,
        unobserved=(),
    )


def test_what_was_not_observed_is_said() -> None:
    started_inside = observed_passage(along_of(np.array([[0.1, 0.2], [2.1, 2.2]])), 2.0, ('a', 'b'))
    assert started_inside.passing_time_s is None and not started_inside.entrance_observed
    assert started_inside.unobserved == ('no robot was seen before the entrance before the first one reached it',)
    assert started_inside.robots_passed == 2 and started_inside.last_exit_s == 1.0
    stuck = observed_passage(along_of(np.array([[-0.1, -0.3], [0.5, -0.2], [2.5, 1.0]])), 2.0, ('a', 'b'))
    assert stuck.never_inside == () and stuck.not_exited == ('b',) and stuck.last_exit_s is None
    assert stuck.unobserved == ('not seen past the exit after being inside: b',) and stuck.robots_passed == 1
    outside = observed_passage(along_of(np.array([[-0.1], [1.0], [2.5]]), clearance=-0.3), 2.0, ('c',))
    assert outside.never_inside == ('c',) and outside.unobserved == ('never seen inside the tube: c',)
    before = observed_passage(along_of(np.array([[-1.0], [-0.5]])), 2.0, ('d',))
    assert before.first_entry_s is None and before.unobserved[0] == 'no robot was seen at or past the entrance'


START = FlightStart(iteration=120, robotarium_time_s=3.96, t_s=1.0)


def test_a_recorded_flight_is_timed_from_its_start_though_every_robot_starts_inside() -> None:
    l_m = np.array([[-0.4, -0.3], [0.1, 0.2], [1.0, 0.5], [2.1, 1.5], [2.5, 2.0]])  # L = 2; the flight starts at t = 1
    passage = recorded_passage(along_of(l_m), 2.0, ('a', 'b'), START)
    assert passage.passing_time_s == 4.0 - 1.0 and passage.first_entry_s == 1.0 and passage.last_exit_s == 4.0
    assert passage.robots_passed == 2 and passage.unobserved == () and not passage.entrance_observed
    assert passage.start == 'start recorded by the flight at t = 1.00 s, after an initialization of 120 steps (3.96 s)'
    inferred = observed_passage(along_of(l_m[1:]), 2.0, ('a', 'b'))  # the same frames without the record
    assert inferred.passing_time_s is None and inferred.start == INFERRED_START


def test_a_recorded_flight_names_the_robots_that_did_not_pass() -> None:
    l_m = np.array([[0.1, -0.5, 0.3], [1.0, -0.5, 2.5], [2.5, -0.4, 2.6]])
    start = FlightStart(0, 0.0, 0.0)
    passage = recorded_passage(along_of(l_m), 2.0, ('a', 'b', 'c'), start)
    assert passage.passing_time_s is None and passage.last_exit_s is None and passage.first_entry_s == 0.0
    assert passage.never_inside == ('b',) and passage.not_exited == () and passage.robots_passed == 2
    assert passage.unobserved == ('never seen at or past the entrance: b',)
    assert passage.start.endswith('no initialization before it')
    stuck = recorded_passage(along_of(np.array([[0.1, 0.2], [2.1, 1.0]])), 2.0, ('a', 'b'), start)
    assert stuck.not_exited == ('b',) and stuck.unobserved == ('not seen past the exit: b',)


def test_a_recorded_start_is_read_on_the_trajectory_s_clock_or_refused_with_the_fix() -> None:
    record = {'iteration': 57, 'robotarium_time_s': 1.881, 't_s': 2.5}
    start = FlightStart.from_record(record, 'folder', first_t_s=0.5)
    assert start == FlightStart(57, 1.881, 2.0) and FlightStart.from_record(start.to_record(), 'x') == start
    assert FlightStart.from_record(None, 'folder') is None  # earlier submissions: inferred
    with pytest.raises(AnalysisError, match="folder: the recorded flight start .* must hold 'iteration'"):
        FlightStart.from_record({'iteration': 3}, 'folder')
    with pytest.raises(AnalysisError, match='needs a step count >= 0 and finite times'):
        FlightStart.from_record(record | {'t_s': float('nan')}, 'folder')
