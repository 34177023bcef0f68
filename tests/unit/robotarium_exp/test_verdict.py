"""The verdict on a run: would the testbed run it, and what duration to declare."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

import robotarium_exp.verdict
from robotarium_exp.spec import ROBOTARIUM
from robotarium_exp.verdict import VerifierVerdict
from robotarium_exp.verifier import VerifierCounts


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
