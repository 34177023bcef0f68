"""The initializer's durations reused between checks: keyed by what they depend on, run only for seeds not stored.

Oracle: `robotarium_exp.initializer.initializer_durations` itself (V2's steps 352 and 512 for seeds 0 and 1 of a
single robot, ``tests/unit/robotarium_exp/test_initializer.py``), called directly.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from robotarium_exp.initializer import initializer_durations
from submission import reuse

IC = np.array([[0.3], [0.2], [2.5]])


@pytest.fixture
def ran(monkeypatch):
    """The seeds each call of the initializer ran (in this process: one worker)."""
    calls: list[list[int]] = []

    def counted(ic, seeds, limit, seed_done=None, ran=None):
        calls.append(list(seeds))
        return initializer_durations(ic, seeds, limit, workers=1, seed_done=seed_done, ran=ran)

    monkeypatch.setattr(reuse, 'initializer_durations', counted)
    return calls


def test_seeds_run_once_then_come_from_the_cache_as_the_initializer_gives_them(tmp_path, ran) -> None:
    done: list[int] = []
    first = reuse.cached_initializer_durations(IC, [1, 0], 400, seed_done=lambda: done.append(1), folder=tmp_path)
    assert first == initializer_durations(IC, [1, 0], 400, workers=1) and ran == [[1, 0]] and len(done) == 2
    assert first.stuck_seeds == (1,)  # seed 1 takes 512 steps: stuck under 400, stored as such
    again = reuse.cached_initializer_durations(IC, [0, 2, 1, 0], 400, seed_done=lambda: done.append(1), folder=tmp_path)
    assert again == initializer_durations(IC, [0, 2, 1, 0], 400, workers=1)
    assert ran == [[1, 0], [2]] and len(done) == 6  # only seed 2 is new; progress counts every seed asked for
    other_limit = reuse.cached_initializer_durations(IC, [1], 600, folder=tmp_path)
    assert other_limit.durations_s == pytest.approx((512 * 0.033,)) and ran[-1] == [1]


def test_each_seed_is_kept_as_it_ends_so_an_interrupted_check_keeps_what_ran(tmp_path, monkeypatch) -> None:
    def interrupted(ic, seeds, limit, seed_done=None, ran=None):
        real = initializer_durations(ic, seeds[:1], limit, workers=1)
        ran(seeds[0], real.durations_s[0])
        raise KeyboardInterrupt

    monkeypatch.setattr(reuse, 'initializer_durations', interrupted)
    with pytest.raises(KeyboardInterrupt):
        reuse.cached_initializer_durations(IC, [0, 1, 2], 400, folder=tmp_path)
    path = tmp_path / reuse.FOLDER / f'{reuse.initializer_key(IC, 400)}.json'
    assert json.loads(path.read_text(encoding='utf-8'))['durations_s'] == {'0': pytest.approx(352 * 0.033)}


def shipped(tmp_path, monkeypatch, formations: object) -> None:
    table = tmp_path / 'shipped.json'
    table.write_text(json.dumps({'formations': formations}), encoding='utf-8')
    monkeypatch.setattr(reuse, 'SHIPPED', table)


def test_a_shipped_formations_durations_are_taken_for_its_key_only(tmp_path, monkeypatch, ran) -> None:
    """A shipped table's seeds for the same key are used without a run (durations made up to tell them apart:
    the real seed 0 takes 352 steps); the user's cache comes first; another key runs its seeds."""
    entry = {'key': reuse.initializer_key(IC, 400), 'durations_s': {'0': 1.5, '1': None, '2': 2.5}}
    shipped(tmp_path, monkeypatch, [entry])
    sample = reuse.cached_initializer_durations(IC, [0, 1, 2], 400, folder=tmp_path / 'cache')
    assert sample.durations_s == (1.5, 2.5) and sample.stuck_seeds == (1,) and ran == []
    both = reuse.cached_initializer_durations(IC, [0, 3], 400, folder=tmp_path / 'cache')
    assert both.durations_s == (1.5, *initializer_durations(IC, [3], 400, workers=1).durations_s) and ran == [[3]]
    cached = tmp_path / 'cache' / reuse.FOLDER / f'{entry["key"]}.json'
    cached.write_text(json.dumps({'durations_s': {'0': 9.0}}), encoding='utf-8')
    assert reuse.cached_initializer_durations(IC, [0], 400, folder=tmp_path / 'cache').durations_s == (9.0,)
    other = reuse.cached_initializer_durations(IC, [0], 600, folder=tmp_path / 'cache')
    assert other.durations_s == pytest.approx((352 * 0.033,)) and ran[-1] == [0]


@pytest.mark.parametrize(
    'formations', ['not a list', [{'key': 'k'}], [{'durations_s': {}}], [{'key': 1, 'durations_s': {'x': 1}}]]
)
def test_a_shipped_table_that_is_not_such_a_table_is_ignored(tmp_path, monkeypatch, formations) -> None:
    shipped(tmp_path, monkeypatch, formations)
    assert reuse.shipped_durations() == {}


def test_the_key_is_what_the_durations_depend_on() -> None:
    key = reuse.initializer_key(IC, 400)
    assert key == reuse.initializer_key(IC.copy(), 400)
    assert key != reuse.initializer_key(IC, 401)
    assert key != reuse.initializer_key(IC + np.array([[1e-12], [0.0], [0.0]]), 400)


RUN_ONE_SEED = """
import json, sys
import numpy as np
from robotarium_exp.initializer import initializer_durations
initializer_durations(np.array([[0.3], [0.2], [2.5]]), [0], 400, workers=1)
print(json.dumps(sorted(sys.modules)))
"""


def test_the_key_holds_every_module_the_initializer_runs_and_not_the_tube_experiment() -> None:
    """Oracle: a fresh process that runs the initializer: every module of ``robotarium_exp`` it loads is in the key;
    the tube experiment's design, packing, parking slots and flight are not (a change to them keeps the durations:
    the first twenty-robot build after the packing came ran its 200 seeds again, 70 minutes)."""
    ran = subprocess.run([sys.executable, '-c', RUN_ONE_SEED], check=True, capture_output=True, text=True)
    loaded = {name for name in json.loads(ran.stdout) if name.startswith('robotarium_exp')}
    names = {name for name, _ in reuse.initializer_sources()}
    for module in loaded:
        parts = module.split('.')[1:]
        assert '/'.join(parts) + '.py' in names or '/'.join([*parts, '__init__.py']) in names, module
    assert {'rps/robotarium.py', 'initializer.py', 'rps_alias.py', 'rps/utilities/barrier_certificates.py'} <= names
    assert not names & {'flight.py', 'design.py', 'packing.py', 'parking_slots.py', 'experiment.py', 'fit.py'}


def test_a_file_that_is_not_a_map_of_durations_is_run_again_and_replaced(tmp_path, ran) -> None:
    path = tmp_path / reuse.FOLDER / f'{reuse.initializer_key(IC, 400)}.json'
    path.parent.mkdir(parents=True)
    for text in ('not json', '[1, 2]', json.dumps({'durations_s': {'0': 'soon'}})):
        path.write_text(text, encoding='utf-8')
        ran.clear()
        assert reuse.cached_initializer_durations(IC, [0], 400, folder=tmp_path).durations_s == pytest.approx(
            (352 * 0.033,)
        )
        assert ran == [[0]]
    assert json.loads(path.read_text(encoding='utf-8'))['durations_s'] == {'0': pytest.approx(352 * 0.033)}


def test_a_cache_that_cannot_be_written_costs_only_the_runs(tmp_path, ran) -> None:
    (tmp_path / reuse.FOLDER).write_text('a file where the folder should be', encoding='utf-8')
    sample = reuse.cached_initializer_durations(IC, [0], 400, folder=tmp_path)
    assert sample.durations_s == pytest.approx((352 * 0.033,)) and ran == [[0]]


def test_the_folder_is_the_users_cache_never_the_repository(monkeypatch, tmp_path) -> None:
    monkeypatch.setenv(reuse.CACHE_ENV, str(tmp_path / 'own'))
    assert reuse.cache_folder() == tmp_path / 'own'
    monkeypatch.delenv(reuse.CACHE_ENV)
    monkeypatch.setenv('XDG_CACHE_HOME', str(tmp_path / 'xdg'))
    assert reuse.cache_folder() == tmp_path / 'xdg' / 'vtube'
    monkeypatch.delenv('XDG_CACHE_HOME')
    monkeypatch.setenv('HOME', str(tmp_path / 'home'))
    assert reuse.cache_folder() == tmp_path / 'home' / '.cache' / 'vtube'


def test_initialized_states_read_back_as_kept_and_a_bad_file_reads_as_none(tmp_path) -> None:
    states = reuse.InitializedStates(tmp_path)
    state = {'_poses': np.arange(6.0).reshape(3, 2), '_iteration': np.array(7), '_called_step_already': np.array(True)}
    states.keep('k', state)
    back = states.recall('k')
    assert back is not None and set(back) == set(state)
    assert all(np.array_equal(back[name], value) and back[name].dtype == value.dtype for name, value in state.items())
    assert states.recall('missing') is None
    (tmp_path / reuse.STATES_FOLDER / 'bad.npz').write_bytes(b'not an npz')
    assert states.recall('bad') is None
    (tmp_path / reuse.STATES_FOLDER / 'pickled.npz').write_bytes(b'')
    np.savez(tmp_path / reuse.STATES_FOLDER / 'pickled.npz', x=np.array([{'a': 1}], dtype=object))
    assert states.recall('pickled') is None  # object arrays need pickle: refused, never unpickled
    assert states.salt == reuse.InitializedStates(tmp_path).salt == reuse.simulator_salt()


def test_initialized_states_that_cannot_be_written_cost_only_the_initialization(tmp_path) -> None:
    (tmp_path / reuse.STATES_FOLDER).write_text('a file where the folder should be', encoding='utf-8')
    reuse.InitializedStates(tmp_path).keep('k', {'_iteration': np.array(1)})
    assert reuse.InitializedStates(tmp_path).recall('k') is None
