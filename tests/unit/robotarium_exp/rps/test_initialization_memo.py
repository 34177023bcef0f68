"""The initialized state recalled from a memo: the run after it is bit for bit the run after V2's initialization.

Oracle: the same construction and loop without a memo (seeded alike), compared on every pose, command, sensor
reading and counter, and on the generators' states at the end, under the ideal and the fitted testbed model.
"""

from __future__ import annotations

import contextlib
import io
import random
from typing import Any

import numpy as np
import pytest

import robotarium_exp.rps.robotarium as simulator
from robotarium_exp.rps import initialization_memo
from robotarium_exp.rps_alias import seed_rps

IC = np.array([[0.3, -0.4], [0.2, -0.3], [2.5, 0.0]])  # two robots: the barrier acts
ONE = IC[:, :1]  # one robot: a quick initialization (352 steps for seed 0)
STEPS = 120


class DictMemo:
    salt = b'test'

    def __init__(self) -> None:
        self.states: dict[str, initialization_memo.State] = {}
        self.recalled = 0

    def recall(self, key: str) -> initialization_memo.State | None:
        state = self.states.get(key)
        self.recalled += state is not None
        return None if state is None else {name: value.copy() for name, value in state.items()}

    def keep(self, key: str, state: initialization_memo.State) -> None:
        self.states[key] = state


def run(seed: int, model: str, ic: np.ndarray = IC) -> dict[str, Any]:
    """A seeded construction and STEPS steps of a fixed loop: what the simulator held at every step."""
    seed_rps(seed)
    with contextlib.redirect_stdout(io.StringIO()):
        r = simulator.Robotarium(
            number_of_robots=ic.shape[1],
            show_figure=False,
            sim_in_real_time=False,
            initial_conditions=ic,
            testbed_model=model,
        )
    held: dict[str, list[Any]] = {'observed': [], 'poses': [], 'sensors': []}
    for k in range(STEPS):
        held['observed'].append(r.get_poses())
        r.set_velocities(
            np.arange(ic.shape[1]), np.array([[0.05] * ic.shape[1], [0.3 * np.sin(0.1 * k)] * ic.shape[1]])
        )
        r.step()
        held['poses'].append(r._poses.copy())
        held['sensors'].append(np.concatenate([r._encoders.ravel(), r._gyros.ravel(), r._orientations]))
    held['counts'] = [r.iterations, r.initialization_steps, r.errors]
    held['generators'] = [random.random(), float(np.random.rand())]
    return held


def same(a: dict[str, Any], b: dict[str, Any]) -> bool:
    return all(
        np.array_equal(np.array(x), np.array(y))
        for key in ('observed', 'poses', 'sensors')
        for x, y in zip(a[key], b[key])
    ) and (a['counts'], a['generators']) == (b['counts'], b['generators'])


@pytest.fixture
def memo(monkeypatch) -> DictMemo:
    own = DictMemo()
    monkeypatch.setattr(initialization_memo, 'memo', own)
    return own


@pytest.mark.parametrize('model', ['ideal', 'fitted'])
def test_a_recalled_initialization_is_followed_by_the_same_run(monkeypatch, memo: DictMemo, model: str) -> None:
    monkeypatch.setattr(initialization_memo, 'memo', None)
    plain, other = run(0, model), run(1, model)
    monkeypatch.setattr(initialization_memo, 'memo', memo)
    kept = run(0, model)  # initialized, then kept
    assert len(memo.states) == 1 and memo.recalled == 0
    monkeypatch.setattr(simulator.Robotarium, 'initialize', lambda *args: pytest.fail('initialized, not recalled'))
    recalled = run(0, model)
    assert memo.recalled == 1
    assert same(plain, kept) and same(plain, recalled)
    assert not same(plain, other)  # the comparison can tell runs apart


def test_the_initialization_draws_nothing_from_pythons_random(monkeypatch) -> None:
    """The memo keeps only np.random's state: Python's random drew the chargers, before the initialization."""
    monkeypatch.setattr(initialization_memo, 'memo', None)
    seen = []
    initialize = simulator.Robotarium.initialize

    def watched(self, ic):
        seen.append(random.getstate())
        initialize(self, ic)
        seen.append(random.getstate())

    monkeypatch.setattr(simulator.Robotarium, 'initialize', watched)
    run(0, 'ideal')
    assert len(seen) == 2 and seen[0] == seen[1]


def test_the_key_changes_with_what_the_initialization_depends_on(memo: DictMemo) -> None:
    run(0, 'ideal', ONE)
    run(0, 'fitted', ONE)  # the initialization stays ideal: the same state
    assert len(memo.states) == 1 and memo.recalled == 1
    run(1, 'ideal', ONE)
    moved = ONE.copy()
    moved[0, 0] += 1e-9
    run(0, 'ideal', moved)
    memo.salt = b'other sources'
    run(0, 'ideal', ONE)
    assert len(memo.states) == 4 and memo.recalled == 1


def test_a_state_that_does_not_fit_is_not_restored(monkeypatch, memo: DictMemo) -> None:
    monkeypatch.setattr(initialization_memo, 'memo', None)
    plain = run(0, 'ideal', ONE)
    monkeypatch.setattr(initialization_memo, 'memo', memo)
    run(0, 'ideal', ONE)
    (key,) = memo.states
    for broken in ({'_poses': np.zeros((3, 2))}, {'numpy_keys': np.zeros(3, dtype=np.uint32)}, {'_iteration': None}):
        memo.states[key] = {name: value for name, value in memo.states[key].items() if name not in broken} | {
            name: value for name, value in broken.items() if value is not None
        }
        assert same(run(0, 'ideal', ONE), plain)  # initialized again, and kept again
