"""What the testbed's verifier would say of a run: its counts, whether the run would be accepted, what to declare."""

from __future__ import annotations

from dataclasses import dataclass

from robotarium_exp.experiment import ExperimentResult
from robotarium_exp.spec import ROBOTARIUM
from robotarium_exp.verifier import VerifierCounts


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
