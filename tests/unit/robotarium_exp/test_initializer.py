"""The initializer runner: V2's initialization per seed, its durations, the seeds that get stuck, the progress calls.

Oracle: V2's own single-robot initializations (352 and 512 steps for seeds 0 and 1, recorded by running the
official simulator; the same numbers ``tests/unit/robotarium_exp/rps/test_robotarium.py`` checks step for step).
"""

from __future__ import annotations

import numpy as np
import pytest

import robotarium_exp.rps.robotarium as simulator
from robotarium_exp.initializer import InitializerSample, initializer_durations

IC = np.array([[0.3], [0.2], [2.5]])
V2_STEPS = {0: 352, 1: 512}


def test_durations_are_v2_s_steps_times_the_time_step_and_progress_is_counted() -> None:
    calls: list[int] = []
    sample = initializer_durations(IC, [0, 1], workers=1, seed_done=lambda: calls.append(1))
    assert sample.durations_s == pytest.approx((352 * 0.033, 512 * 0.033), abs=1e-12)
    assert sample.stuck_seeds == () and sample.runs == 2 and len(calls) == 2


def test_a_seed_over_the_limit_is_stuck_and_the_limit_is_restored() -> None:
    before = simulator.INITIALIZATION_STEP_LIMIT
    sample = initializer_durations(IC, [1, 0], limit=400, workers=1)
    assert sample == InitializerSample(durations_s=(pytest.approx(352 * 0.033),), stuck_seeds=(1,))
    assert sample.runs == 2 and simulator.INITIALIZATION_STEP_LIMIT == before


def test_no_seeds_no_runs() -> None:
    sample = initializer_durations(IC, [], workers=4)
    assert sample == InitializerSample((), ()) and sample.runs == 0
