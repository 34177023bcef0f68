"""The verdict on a run: would the testbed run it, what duration to declare, and whether the flight succeeded."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import robotarium_exp.verdict
from robotarium_exp.spec import ROBOTARIUM
from robotarium_exp.verdict import BODY_ON_WALL_STEPS_TOLERATED, VerifierVerdict, flight_failures
from robotarium_exp.verifier import VerifierCounts
from tests.support.passage import metrics


@pytest.mark.parametrize(
    ('counts', 'runs'),
    [
        (VerifierCounts(), True),
        (VerifierCounts(actuator=7), True),  # actuator limits are counted, not refused
        (VerifierCounts(too_close=1), False),
        (VerifierCounts(outside=2), False),
    ],
)
def test_would_run_only_without_collisions_and_robots_outside(counts: VerifierCounts, runs: bool) -> None:
    assert VerifierVerdict(counts, 10.0).would_run is runs


def test_declared_duration_and_the_verdict_of_a_result() -> None:
    result = SimpleNamespace(errors=VerifierCounts(0, 0, 3), duration_s=42.0)
    verdict = robotarium_exp.verdict.testbed_verdict(result)  # type: ignore[arg-type]
    assert verdict == VerifierVerdict(VerifierCounts(0, 0, 3), 42.0) and verdict.would_run
    assert verdict.declare_at_least_s == pytest.approx(42.0 * ROBOTARIUM.duration_factor) == pytest.approx(63.0)


def flight(counts: VerifierCounts | None = None, parked: bool = True, **passage: object) -> SimpleNamespace:
    """A flight's result: every robot through and parked, no body on a wall, unless changed."""
    m = metrics(**({'tube_violation_steps': 0, 'robots_outside': 0, 'max_outside_m': 0.0} | passage))
    return SimpleNamespace(errors=counts or VerifierCounts(), duration_s=40.0, metrics=m, completed=parked)


@pytest.mark.parametrize(
    ('result', 'reason'),
    [
        (flight(VerifierCounts(actuator=9)), 'the simulator counted 9 steps over the wheel-speed limit'),  # as check
        (flight(VerifierCounts(too_close=4)), 'the testbed would not run it (4 pair-steps of robots too close, 0 '),
        (flight(VerifierCounts(outside=1)), 'the testbed would not run it (0 pair-steps of robots too close, 1 '),
        (flight(completed=False, robots_passed=6), '2 of 8 robots never passed the exit'),
        (flight(collision_pairs=1, collision_steps=2), '1 robot pairs collided (closer than 0.6 m'),
        (flight(tube_violation_steps=1, robots_outside=1, max_outside_m=0.004), 'robot bodies were on the tube wal'),
        (flight(parked=False), 'not every robot parked beyond the exit by the last step'),
    ],
)
def test_a_flight_fails_for_each_reason_alone(result: SimpleNamespace, reason: str | None) -> None:
    failures = flight_failures(result)  # type: ignore[arg-type]
    assert failures == (() if reason is None else (failures[0],)) and (reason is None or failures[0].startswith(reason))


def test_bodies_on_the_walls_are_tolerated_up_to_none() -> None:
    assert BODY_ON_WALL_STEPS_TOLERATED == 0
    failures = flight_failures(flight(tube_violation_steps=14715, robots_outside=20, max_outside_m=0.25))  # type: ignore[arg-type]
    assert failures == ('robot bodies were on the tube walls in 14715 robot-steps (20 robots, up to 0.250 m over)',)
    every = flight(VerifierCounts(1, 1, 0), parked=False, completed=False, robots_passed=0, collision_pairs=3)
    assert len(flight_failures(every)) == 4  # type: ignore[arg-type]


def test_a_preflight_run_and_a_flight_get_the_one_verdict() -> None:
    """Issue 49: the 8-robot L-shaped tube's flight failed on 33 robot-steps of bodies on a wall while the build's
    preflight of the same run said PASS; both now take `run_failures`, so the same run fails both ways."""
    from submission.check import CheckReport, RunReport
    from submission.recording import SimulatorRecord

    on_wall = flight(tube_violation_steps=33, robots_outside=1, max_outside_m=0.012)
    steps = 4
    poses = np.zeros((steps, 3, 8))
    poses[:, 0] = 0.3 * np.arange(8) - 1.0  # apart, in the arena: the verifier's rules count nothing
    record = SimulatorRecord(poses, np.zeros((steps, 2, 8)), 0.033, {}, steps + 5, 5, 1, True)
    run = RunReport('bundled', 0, 0, record=record, completed=True, metrics=on_wall.metrics)
    assert run.problems == list(flight_failures(on_wall))  # type: ignore[arg-type]
    assert run.problems == ['robot bodies were on the tube walls in 33 robot-steps (1 robots, up to 0.012 m over)']
    assert not CheckReport('f.py', runs=(run,)).passed
    clean = RunReport('bundled', 0, 0, record=record, completed=True, metrics=flight().metrics)
    assert clean.ok and CheckReport('f.py', runs=(clean,)).passed
