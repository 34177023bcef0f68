"""What the testbed's verifier would say of a run: its counts, whether the run would be accepted, what to declare."""

from __future__ import annotations

from dataclasses import dataclass

from robotarium_exp.experiment import ExperimentResult
from robotarium_exp.spec import ROBOTARIUM


@dataclass(frozen=True)
class VerifierVerdict:
    """The simulator's validation counts of a run (pair-steps too close, robot-steps outside the arena,
    actuator-limit steps) and its duration, initialization included (s)."""

    too_close: int
    outside: int
    actuator: int
    duration_s: float

    @property
    def would_run(self) -> bool:
        """No robots too close and none outside: the testbed would run the experiment."""
        return self.too_close + self.outside == 0

    @property
    def declare_at_least_s(self) -> float:
        """The shortest duration to declare for this run, by the spec's duration factor."""
        return ROBOTARIUM.duration_factor * self.duration_s


def testbed_verdict(result: ExperimentResult) -> VerifierVerdict:
    """The verdict on an experiment flown on a Robotarium simulator."""
    errors = result.errors
    return VerifierVerdict(
        too_close=errors['robots_too_close'],
        outside=errors['robots_outside_boundaries'],
        actuator=errors['exceeded_actuator_limits'],
        duration_s=result.duration_s,
    )
