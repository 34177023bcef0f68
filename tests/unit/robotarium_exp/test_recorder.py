"""The recorder: either generation's Robotarium that also logs every pose it hands out."""

from __future__ import annotations

import numpy as np

import robotarium_exp.rps_classic.robotarium_abc as classic_abc
from robotarium_exp.recorder import recording
from robotarium_exp.rps.robotarium import Robotarium as V2
from robotarium_exp.rps_classic.robotarium import Robotarium as Classic
from vtube_planning.log import read_log

IC = np.array([[0.0, 0.6], [0.0, 0.0], [0.0, np.pi / 2]])


def drive(r, steps: int) -> list[np.ndarray]:
    seen = []
    for _ in range(steps):
        seen.append(np.array(r.get_poses()))  # classic hands out its own array
        r.set_velocities(np.arange(2), np.array([[0.1, 0.05], [0.0, 0.5]]))
        r.step()
    return seen


def test_v2_recording_logs_each_pose_and_the_counts_at_debug(tmp_path) -> None:
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
    assert meta['kind'] == 'bundled robotarium' and meta['n_robots'] == 2 and meta['dt_s'] == 0.033
    assert meta['finished'] and meta['iterations'] == 3 and meta['errors'] == r.errors


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
