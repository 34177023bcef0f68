"""Fixtures of the vtube_planning unit tests."""

from __future__ import annotations

import pytest

import vtube_planning.studies.campaign_runner as campaign_module
from tests.support.campaigns import fake_metrics
from vtube_planning.studies.study import Point, RunSettings


@pytest.fixture
def fake_runs(monkeypatch):
    """Replace the simulation with :func:`fake_metrics`; ``calls`` lists the points run; ``fail`` maps a call number
    to the exception it raises."""
    calls: list[Point] = []
    fail: dict[int, BaseException] = {}

    def run(point: Point, settings: RunSettings) -> dict[str, object]:
        calls.append(point)
        if len(calls) in fail:
            raise fail[len(calls)]
        return fake_metrics(point)

    monkeypatch.setattr(campaign_module, 'run_point', run)
    return calls, fail
