"""What the testbed's verifier would say of a run (its counts, whether it would run, what to declare), and whether
the flight succeeded."""

from __future__ import annotations

from dataclasses import dataclass

from robotarium_exp.experiment import ExperimentResult
from robotarium_exp.spec import ROBOTARIUM
from robotarium_exp.verifier import VerifierCounts
from vtube_planning.swarm.metrics import passage_failures

BODY_ON_WALL_STEPS_TOLERATED = 0
"""Robot-steps a flight may have with a robot's body on or over a tube wall (its centre closer to the wall than
the body radius, while 0 <= l <= L): none. A body on the wall is a robot touching the tube the experiment shows it
keeps to; both shipped scenes fly with none, planned and unplanned, over the V2 initialization seeds of docs/robotarium_compare/."""


@dataclass(frozen=True)
class VerifierVerdict:
    """The simulator's validation counts of a run and its duration, initialization included (s)."""

    counts: VerifierCounts
    duration_s: float

    @property
    def would_run(self) -> bool:
        """No robots too close and none outside: the testbed would run the experiment."""
        return self.counts.too_close + self.counts.outside == 0

    @property
    def declare_at_least_s(self) -> float:
        """The shortest duration to declare for this run, by the spec's duration factor."""
        return ROBOTARIUM.duration_factor * self.duration_s


def testbed_verdict(result: ExperimentResult) -> VerifierVerdict:
    """The verdict on an experiment flown on a Robotarium simulator."""
    return VerifierVerdict(result.errors, result.duration_s)


def flight_failures(result: ExperimentResult) -> tuple[str, ...]:
    """Why a flight on a Robotarium failed, one reason each: the testbed would not run it, a robot never passed
    the exit, robots collided ([`passage_failures`][vtube_planning.swarm.metrics.passage_failures]), bodies were on the
    walls (more than `BODY_ON_WALL_STEPS_TOLERATED`), a robot did not park. Empty: the flight succeeded."""
    counts, metrics = result.errors, result.metrics
    failures = []
    if not testbed_verdict(result).would_run:
        failures.append(
            f'the testbed would not run it ({counts.too_close} pair-steps of robots too close, {counts.outside} '
            'robot-steps outside the arena)'
        )
    failures += passage_failures(metrics)
    if metrics.tube_violation_steps > BODY_ON_WALL_STEPS_TOLERATED:
        failures.append(
            f'robot bodies were on the tube walls in {metrics.tube_violation_steps} robot-steps '
            f'({metrics.robots_outside} robots, up to {metrics.max_outside_m:.3f} m over)'
        )
    if not result.completed:
        failures.append('not every robot parked beyond the exit by the last step')
    return tuple(failures)
