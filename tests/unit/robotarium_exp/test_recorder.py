"""The one recorder of a run on a Robotarium class: what the simulator held at each step after the initialization,
on a fake V2-like simulator, on either bundled generation and under a testbed model, written as a vtube log."""

from __future__ import annotations

import numpy as np
import pytest

import robotarium_exp.rps_classic.robotarium_abc as classic_abc
from robotarium_exp.recorder import Recorder, counters, recorded, recording, time_step_s
from robotarium_exp.rps.robotarium import Robotarium as V2
from robotarium_exp.rps_classic.robotarium import Robotarium as Classic
from vtube_planning.log import read_log

IC = np.array([[0.0, 0.6], [0.0, 0.0], [0.0, np.pi / 2]])
COMMANDS = np.array([[0.1, 0.05], [0.0, 0.5]])
CLASSIC_LIKE = type(
    'Classic', (), {'_errors': {'collision': 2, 'collision_string': 'x', 'flag': True}, '_iterations': 7}
)
CLASSIC_LIKE = type(
    'Classic', (), {'_errors': {'collision': 2, 'collision_string': 'x', 'flag': True}, '_iterations': 7}
)


class Simulator:
    """A V2-like simulator: private poses and commands, an initialization phase, counters with a text beside them."""

    TIME_STEP = 0.033

    def __init__(self, number_of_robots: int) -> None:
        self.number_of_robots = number_of_robots
        self._poses = np.zeros((3, number_of_robots))
        self._velocities = np.zeros((2, number_of_robots))
        self._errors = {'robots_too_close': 1, 'boundary_text': 'x'}
        self._iteration = 0
        self.initializing = True

    def step(self) -> None:
        self._iteration += 1
        self._poses = self._poses + 1.0

    def debug(self) -> None:
        pass


def drive(r, steps: int) -> list[np.ndarray]:
    """``steps`` periods as a script flies them; the poses handed out."""
    seen = []
    for _ in range(steps):
        seen.append(np.array(r.get_poses()))  # classic hands out its own array
        r.set_velocities(np.arange(2), COMMANDS)
        r.step()
    return seen


def test_each_step_after_the_initialization_is_recorded_with_the_counters(tmp_path) -> None:
    recorder = Recorder(tmp_path / 'r.npz', {'kind': 'test'})
    cls = recorded(Simulator, recorder)
    assert cls.__name__ == 'Simulator' and not hasattr(cls, 'call_at_scripts_end')  # only the generation's own
    r = cls(number_of_robots=2)
    r.step()
    r.step()  # two steps of initialization: counted, not recorded
    r.initializing = False
    r._velocities = np.ones((2, 2))
    r.step()
    r.step()
    cls(number_of_robots=3).step()  # a second object: counted, not recorded (the testbed runs one)
    r.debug()
    assert r.vtube_initialization_steps == 2 and r.vtube_end_of_script
    assert recorder.finish() == tmp_path / 'r.npz'
    arrays, meta = read_log(tmp_path / 'r.npz')
    np.testing.assert_array_equal(arrays['positions_m'], np.stack([np.full((2, 2), 2.0), np.full((2, 2), 3.0)]))
    np.testing.assert_array_equal(arrays['headings_rad'], np.stack([np.full(2, 2.0), np.full(2, 3.0)]))
    np.testing.assert_array_equal(arrays['commands'], np.ones((2, 2, 2)))
    np.testing.assert_allclose(arrays['t_s'], [0.0, 0.033])
    assert {k: meta[k] for k in ('kind', 'n_robots', 'dt_s', 'iterations', 'initialization_steps')} == {
        'kind': 'test',
        'n_robots': 2,
        'dt_s': 0.033,
        'iterations': 4,
        'initialization_steps': 2,
    }
    assert meta['errors'] == {'robots_too_close': 1} and meta['robotariums'] == 2 and meta['end_of_script']


def test_a_script_without_a_robotarium_leaves_an_empty_finished_log(tmp_path) -> None:
    Recorder(tmp_path / 'r.npz', {'kind': 'test'}).finish()
    arrays, meta = read_log(tmp_path / 'r.npz')
    assert arrays['positions_m'].shape == (0, 2, 0) and arrays['commands'].shape == (0, 2, 0)
    assert meta['finished'] and meta['robotariums'] == 0 and not meta['end_of_script'] and meta['dt_s'] == 0.0


def test_v2_recording_logs_each_step_and_the_counts_at_debug(tmp_path) -> None:
    log = tmp_path / 'run.npz'
    cls = recording(V2, str(log))
    assert cls.__name__ == 'Robotarium' and issubclass(cls, V2) and not hasattr(cls, 'call_at_scripts_end')
    r = cls(number_of_robots=2, show_figure=False, sim_in_real_time=False, initial_conditions=IC,
            skip_initialization=True)  # fmt: skip
    seen = drive(r, 3)
    assert not log.exists()  # completed only by the end-of-script call
    r.debug()
    arrays, meta = read_log(log)
    np.testing.assert_allclose(arrays['t_s'], [0.0, 0.033, 0.066])
    np.testing.assert_array_equal(arrays['positions_m'], np.stack([p[:2] for p in seen]))
    np.testing.assert_array_equal(arrays['headings_rad'], np.stack([p[2] for p in seen]))
    np.testing.assert_array_equal(arrays['commands'], np.stack([COMMANDS] * 3))
    assert meta['kind'] == 'bundled robotarium' and meta['n_robots'] == 2 and meta['dt_s'] == 0.033
    assert meta['finished'] and meta['iterations'] == 3 and meta['errors'] == r.errors


def test_under_a_testbed_model_the_true_poses_are_recorded(tmp_path) -> None:
    log = tmp_path / 'run.npz'
    r = recording(V2, str(log))(number_of_robots=2, show_figure=False, sim_in_real_time=False,
                                initial_conditions=IC, skip_initialization=True, testbed_model='fitted')  # fmt: skip
    true_poses = []
    for _ in range(20):
        r.get_poses()
        true_poses.append(r._poses.copy())  # what the verifier judges, not the noisy reading handed out
        r.set_velocities(np.arange(2), COMMANDS)
        r.step()
    r.debug()
    arrays, _ = read_log(log)
    np.testing.assert_array_equal(arrays['positions_m'], np.stack([p[:2] for p in true_poses]))


def test_classic_recording_completes_at_call_at_scripts_end(tmp_path, capsys) -> None:
    classic_abc.SHARED_ERRORS.clear()
    log = tmp_path / 'classic.npz'
    cls = recording(Classic, str(log))
    assert issubclass(cls, Classic) and not hasattr(cls, 'debug')
    r = cls(number_of_robots=2, show_figure=False, sim_in_real_time=False, initial_conditions=IC)
    seen = drive(r, 2)
    r.call_at_scripts_end()
    arrays, meta = read_log(log)
    np.testing.assert_array_equal(arrays['positions_m'], np.stack([p[:2] for p in seen]))
    np.testing.assert_allclose(arrays['t_s'], [0.0, 0.033])
    assert meta['iterations'] == 2 and all(isinstance(v, int) for v in meta['errors'].values())
    assert 'No errors in your simulation' in capsys.readouterr().out
    classic_abc.SHARED_ERRORS.clear()


@pytest.mark.parametrize(
    ('robotarium', 'expected'),
    [
        (Simulator(1), ({'robots_too_close': 1}, 0)),
        (CLASSIC_LIKE(), ({'collision': 2}, 7)),
        (object(), ({}, 0)),
    ],
)
def test_counters_keep_the_integer_counts_of_either_generation(robotarium: object, expected: tuple) -> None:
    assert counters(robotarium) == expected


def test_the_time_step_of_either_generation() -> None:
    assert time_step_s(Simulator) == 0.033 and time_step_s(type('C', (), {'time_step': 0.05})) == 0.05
    assert time_step_s(object()) == 0.0
