"""What the preflight records of a run (the one recorder, `robotarium_exp.recorder`, tested there) read back as the
simulator's record; the runner in this process on a tiny script."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import robotarium_exp.rps as rps_package
from robotarium_exp.recorder import recorded
from robotarium_exp.rps import robotarium as v2
from submission import recording
from submission.errors import CheckError
from submission.recording import KIND, read_record, recorder_for
from vtube_planning.log import LOG_FORMAT, LOG_VERSION
from vtube_planning.npzfile import write_npz

IC = np.array([[-0.5, 0.5], [0.0, 0.0], [0.0, 0.0]])


def test_a_preflight_recording_reads_back_as_the_simulator_record(tmp_path) -> None:
    recorder = recorder_for(tmp_path / 'r.npz', 'bundled')
    cls = recorded(v2.Robotarium, recorder)
    r = cls(number_of_robots=2, show_figure=False, sim_in_real_time=False, initial_conditions=IC,
            skip_initialization=True)  # fmt: skip
    r.initializing = True  # as V2's constructor is while it drives the robots from the chargers
    for _ in range(2):
        r.get_poses()
        r.step()
    r.initializing = False
    steps = r.iterations  # those steps: counted, not recorded
    for _ in range(3):
        r.get_poses()
        r.set_velocities(np.arange(2), np.array([[0.05, 0.05], [0.0, 0.0]]))
        r.step()
    r.debug()
    recorder.finish()
    read = read_record(tmp_path / 'r.npz')
    assert read.poses.shape == (3, 3, 2) and read.commands.shape == (3, 2, 2)
    assert (read.dt_s, read.iterations, read.initialization_steps, read.experiment_steps) == (
        0.033,
        steps + 3,
        steps,
        3,
    )
    assert read.errors == r.errors and read.robotariums == 1 and read.end_of_script


def test_a_script_without_a_robotarium_leaves_an_empty_record(tmp_path) -> None:
    recorder_for(tmp_path / 'r.npz', 'pypi').finish()
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
