"""What the preflight records of a run: a Robotarium class that copies what each step validates, written as a
vtube log and read back; the runner in this process on a tiny script."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import robotarium_exp.rps as rps_package
from robotarium_exp.recorder import time_step_s
from robotarium_exp.rps import robotarium as v2
from robotarium_exp.rps_classic import robotarium as classic
from submission import recording
from submission.errors import CheckError
from submission.recording import KIND, _Recorder, read_record, recorded
from vtube_planning.log import LOG_FORMAT, LOG_VERSION
from vtube_planning.npzfile import write_npz


class Simulator:
    """A V2-like simulator: private poses and commands, an initialization phase, counters and iterations."""

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


def test_the_recorded_class_copies_each_step_after_the_initialization(tmp_path) -> None:
    recorder = _Recorder()
    cls = recorded(Simulator, recorder)
    assert cls.__name__ == 'Simulator' and not hasattr(cls, 'call_at_scripts_end')  # only the generation's own
    r = cls(number_of_robots=2)
    r.step()
    r.step()  # two steps of initialization: counted, not recorded
    r.initializing = False
    r._velocities = np.ones((2, 2))
    r.step()
    r.step()
    r.debug()
    assert r.vtube_initialization_steps == 2 and len(r.vtube_rows) == 2 and r.vtube_end_of_script
    np.testing.assert_array_equal(r.vtube_rows[0][0], np.full((3, 2), 2.0))  # the poses step() was handed
    recorder.write(tmp_path / 'r.npz', 'bundled')
    read = read_record(tmp_path / 'r.npz')
    assert read.poses.shape == (2, 3, 2) and read.commands.shape == (2, 2, 2)
    np.testing.assert_array_equal(read.poses[1], np.full((3, 2), 3.0))
    assert (read.dt_s, read.iterations, read.initialization_steps, read.experiment_steps) == (0.033, 4, 2, 2)
    assert read.errors == {'robots_too_close': 1} and read.robotariums == 1 and read.end_of_script


def test_a_script_without_a_robotarium_leaves_an_empty_record(tmp_path) -> None:
    _Recorder().write(tmp_path / 'r.npz', 'pypi')
    read = read_record(tmp_path / 'r.npz')
    assert read.robotariums == 0 and read.poses.shape == (0, 3, 0) and not read.end_of_script and read.dt_s == 0.0


def test_a_log_of_another_kind_is_not_a_record(tmp_path) -> None:
    meta = {'format': LOG_FORMAT, 'version': LOG_VERSION, 'kind': 'simulation'}
    write_npz(tmp_path / 'sim.npz', {'t_s': np.zeros(1), 'positions_m': np.zeros((1, 2, 1))}, meta)
    with pytest.raises(CheckError, match=f"is a vtube log of kind 'simulation', not a {KIND}"):
        read_record(tmp_path / 'sim.npz')
    (tmp_path / 'bad.npz').write_bytes(b'not a zip')
    with pytest.raises(CheckError):
        read_record(tmp_path / 'bad.npz')


def test_both_generations_keep_their_own_end_of_script_call() -> None:
    v2_cls, classic_cls = recorded(v2.Robotarium, _Recorder()), recorded(classic.Robotarium, _Recorder())
    assert hasattr(v2_cls, 'debug') and not hasattr(v2_cls, 'call_at_scripts_end')
    assert hasattr(classic_cls, 'call_at_scripts_end') and issubclass(classic_cls, classic.Robotarium)
    assert time_step_s(Simulator) == 0.033 and time_step_s(object()) == 0.0
    assert recording._iterations(Simulator(1)) == 0 and recording._iterations(object()) == 0


def test_the_runner_records_a_script_on_the_bundled_simulator(tmp_path, monkeypatch) -> None:
    """``python -m submission.recording`` in this process: ``import rps`` resolved to the bundled simulator."""
    script = tmp_path / 'script.py'
    script.write_text(
        'import numpy as np\n'
        'import rps.robotarium as robotarium\n'
        'ic = np.array([[-0.5, 0.5], [0.0, 0.0], [0.0, 0.0]])\n'
        'r = robotarium.Robotarium(number_of_robots=2, show_figure=False, sim_in_real_time=False, '
        'initial_conditions=ic)\n'
        'for _ in range(3):\n'
        '    r.get_poses()\n'
        '    r.set_velocities(np.arange(2), np.array([[0.05, 0.05], [0.0, 0.0]]))\n'
        '    r.step()\n'
        'r.debug()\n'
    )
    for name in [name for name in sys.modules if name == 'rps' or name.startswith('rps.')]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setattr(sys, 'argv', list(sys.argv))
    monkeypatch.setattr(sys, 'meta_path', list(sys.meta_path))  # the runner's rps finder: for this test only
    with monkeypatch.context() as patch:
        patch.setenv('VTUBE_HEADLESS', '1')
        recording.main(['--simulator', 'bundled', '--seed', '0', '--record', str(tmp_path / 'r.npz'), str(script)])
    for name in [name for name in sys.modules if name == 'rps' or name.startswith('rps.')]:
        del sys.modules[name]  # what the runner installed: only for its own process
    assert rps_package.robotarium is v2  # the runner's rps.robotarium is a copy: our package is left as it was
    read = read_record(tmp_path / 'r.npz')
    assert read.robotariums == 1 and read.end_of_script and read.experiment_steps == 3
    assert read.poses.shape[2] == 2 and read.commands[0, 0].tolist() == [0.05, 0.05]
