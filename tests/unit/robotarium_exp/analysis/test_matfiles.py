"""Poses from tiny .mat files written here with scipy: layouts, names, time arrays, and what is refused."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.io

from robotarium_exp.analysis.matfiles import POSE_NAMES, TIME_NAMES, read_mat
from robotarium_exp.errors import AnalysisError

RNG = np.random.default_rng(5)
POSES = RNG.uniform(-1, 1, (3, 4, 20))  # MATLAB's layout: x, y, heading of 4 robots over 20 steps


def write(tmp_path, **variables) -> object:
    path = tmp_path / 'run.mat'
    scipy.io.savemat(path, variables)
    return path


def test_matlab_layout_with_its_time(tmp_path) -> None:
    t = 5.0 + 0.04 * np.arange(20)
    t_s, poses, read = read_mat(write(tmp_path, x=POSES, t=t, gains=np.eye(2)))
    np.testing.assert_array_equal(poses, POSES.transpose(2, 0, 1))
    np.testing.assert_allclose(t_s, t - 5.0)
    assert read == {
        'pose_variable': 'x',
        'time': "from the array 't'",
        'ignored': [{'variable': 'gains', 'reason': 'not a pose array'}],
    }


def test_our_layout_found_alone_and_steps_assumed(tmp_path) -> None:
    ours = POSES.transpose(2, 0, 1)  # (T, 3, N)
    t_s, poses, read = read_mat(write(tmp_path, trajectory=ours))
    np.testing.assert_array_equal(poses, ours) and read['pose_variable'] == 'trajectory'
    np.testing.assert_allclose(t_s, 0.033 * np.arange(20))
    assert read['time'] == 'no time array; steps of 0.033 s assumed'
    _, _, bad_time = read_mat(write(tmp_path, poses=POSES, time=np.ones(20)))
    assert bad_time['time'] == "the array 'time' does not increase step by step; steps of 0.033 s assumed"


def test_what_cannot_be_the_poses_is_refused(tmp_path) -> None:
    with pytest.raises(AnalysisError, match=r"several arrays that could be the poses \(\['a', 'b'\]\)"):
        read_mat(write(tmp_path, a=POSES, b=POSES))
    with pytest.raises(AnalysisError, match=r"has no pose array \(3 x N x T\) among its variables \{'v': \[1, 5\]\}"):
        read_mat(write(tmp_path, v=np.arange(5.0)))
    garbage = tmp_path / 'garbage.mat'
    for content in (b'not a mat file at all' * 20, b''):
        garbage.write_bytes(content)
        with pytest.raises(AnalysisError, match='cannot read .* as a MATLAB file'):
            read_mat(garbage)
    assert 'x_data' in POSE_NAMES and 't_s' in TIME_NAMES
