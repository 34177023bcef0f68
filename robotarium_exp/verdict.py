"""What the testbed's verifier would say of a run (its counts, whether it would run, what to declare), and whether
the flight succeeded."""

from __future__ import annotations

from dataclasses import dataclass

from robotarium_exp.experiment import ExperimentResult
from robotarium_exp.spec import ROBOTARIUM
from robotarium_exp.verifier import BODY_ON_WALL_STEPS_TOLERATED, VerifierCounts, wall_failure
from vtube_planning.swarm.metrics import PassageMetrics, passage_failures

__all__ = ['BODY_ON_WALL_STEPS_TOLERATED', 'VerifierVerdict', 'flight_failures', 'run_failures', 'testbed_verdict']


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
    """Why a flight of `robotarium_exp.experiment.run_experiment` failed: `run_failures` of its counts, its
    passage and whether every robot parked. Empty: the flight succeeded."""
    return run_failures(result.errors, result.metrics, parked=result.completed)


def run_failures(counts: VerifierCounts, metrics: PassageMetrics | None, *, parked: bool) -> tuple[str, ...]:
    """The one verdict on a run on a Robotarium, whoever flew it (`vtube robotarium run`, `robotarium compare`,
    the preflight of `submission build` and `submission check`, the demo), one reason each: the testbed would not
    run it, the simulator counted actuator-limit steps, a robot never passed the exit, robots collided
    ([`passage_failures`][vtube_planning.swarm.metrics.passage_failures]), bodies were on the walls (more than
    `BODY_ON_WALL_STEPS_TOLERATED`), a robot did not park. ``metrics``: the passage measured on the robots'
    bodies (None: not measured, judged on the counts and parking alone). Empty: the run succeeded."""
    failures = []
    if not VerifierVerdict(counts, 0.0).would_run:
        failures.append(
            f'the testbed would not run it ({counts.too_close} pair-steps of robots too close, {counts.outside} '
            'robot-steps outside the arena)'
        )
    if counts.actuator:
        failures.append(f'the simulator counted {counts.actuator} steps over the wheel-speed limit')
    if metrics is not None:
        failures += passage_failures(metrics)
        wall = wall_failure(metrics.tube_violation_steps, metrics.robots_outside, metrics.max_outside_m)
        failures += [wall] if wall else []
    if not parked:
        failures.append('not every robot parked beyond the exit by the last step')
    return tuple(failures)
