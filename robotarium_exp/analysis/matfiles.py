"""Robot poses from the ``.mat`` files MATLAB users get back from the Robotarium (plain arrays, via scipy.io).

A MATLAB script on the testbed saves whatever it collected, typically ``get_poses`` stacked over steps: an array
(3, N, T) of x, y and heading. The pose array is found by name (`POSE_NAMES`) or, failing that, as the
only three-dimensional array with x, y, heading along its first axis; an array (T, 3, N) is read as our own
submission's layout. Time is the array named in `TIME_NAMES` when it increases and has one entry per
step; otherwise (absent, or not usable) the steps are the testbed's period, and the report says which.

MATLAB class objects (a ``classdef`` data saver) cannot be read outside MATLAB: the error says how to save plain
arrays instead. MATLAB v7.3 files (HDF5) are refused with the option that writes a readable file.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.errors import AnalysisError
from robotarium_exp.spec import ROBOTARIUM

POSE_NAMES = ('poses', 'pose', 'pose_data', 'x_data', 'x', 'robot_poses', 'vtube_poses')
TIME_NAMES = ('t', 't_s', 'time', 'times', 'vtube_t')
SAVE_HINT = (
    "save plain arrays instead, e.g. in MATLAB: x = data_saver.x_data; save('poses.mat', 'x', '-v7') "
    '(x = get_poses() of every step, stacked as 3 x N x T)'
)


def read_mat(path: Path) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
    """Time (T,) in seconds, poses (T, 3, N), and what was read (pose and time variables, what was ignored)."""
    import warnings

    import scipy.io
    from scipy.io.matlab import MatReadError, MatReadWarning

    try:
        with warnings.catch_warnings():  # class objects come as duplicate variables named 'None': refused below
            warnings.simplefilter('ignore', MatReadWarning)
            variables = scipy.io.loadmat(path, squeeze_me=False)
    except NotImplementedError as err:  # scipy's answer to HDF5-based v7.3 files
        msg = f"{str(path)!r} is a MATLAB v7.3 (HDF5) file, which scipy cannot read; save it with save(..., '-v7')."
        raise AnalysisError(msg) from err
    except (MatReadError, ValueError, TypeError, OSError) as err:
        msg = f'cannot read {str(path)!r} as a MATLAB file: {err}.'
        raise AnalysisError(msg) from err
    arrays = {
        k: v
        for k, v in variables.items()
        if not k.startswith('__') and isinstance(v, np.ndarray) and v.dtype.kind in 'fiu'
    }
    objects = sorted(k for k, v in variables.items() if not k.startswith('__') and k not in arrays)
    name, poses = _pose_array(path, arrays, objects)
    poses = np.asarray(poses, dtype=float)
    steps = poses.shape[2] if _matlab_layout(poses) else poses.shape[0]
    poses = poses.transpose(2, 0, 1) if _matlab_layout(poses) else poses  # -> (T, 3, N)
    t_s, time_note = _time(arrays, steps)
    ignored = [{'variable': k, 'reason': 'not a pose array'} for k in sorted(arrays) if k not in (name, *TIME_NAMES)]
    ignored += [{'variable': k, 'reason': 'not a plain numeric array'} for k in objects]
    return t_s, poses, {'pose_variable': name, 'time': time_note, 'ignored': ignored}


def _matlab_layout(poses: np.ndarray) -> bool:
    return bool(poses.shape[0] == 3)


def _pose_array(path: Path, arrays: dict[str, np.ndarray], objects: list[str]) -> tuple[str, np.ndarray]:
    fits = {k: v for k, v in arrays.items() if v.ndim == 3 and (v.shape[0] == 3 or v.shape[1] == 3)}
    named = [k for k in fits if k.lower() in POSE_NAMES]
    if named:
        return named[0], fits[named[0]]
    if len(fits) == 1:
        return next(iter(fits.items()))
    if len(fits) > 1:
        msg = (
            f'{str(path)!r} holds several arrays that could be the poses ({sorted(fits)}); name the pose array '
            f'one of {list(POSE_NAMES)} (3 x N x T: x, y, heading of N robots over T steps).'
        )
        raise AnalysisError(msg)
    if objects:
        msg = (
            f'{str(path)!r} holds MATLAB class objects ({objects}) and no plain pose array; scipy cannot read '
            f'objects outside MATLAB: {SAVE_HINT}.'
        )
        raise AnalysisError(msg)
    shapes = {k: list(v.shape) for k, v in arrays.items()}
    msg = f'{str(path)!r} has no pose array (3 x N x T) among its variables {shapes}; {SAVE_HINT}.'
    raise AnalysisError(msg)


def _time(arrays: dict[str, np.ndarray], steps: int) -> tuple[np.ndarray, str]:
    """The time array when it is usable, else the testbed's steps, and a note saying which."""
    period = ROBOTARIUM.time_step_s
    fallback = np.arange(steps) * period
    for name in TIME_NAMES:
        if name in arrays:
            t = np.asarray(arrays[name], dtype=float).ravel()
            if t.size == steps and np.all(np.isfinite(t)) and np.all(np.diff(t) > 0):
                return t - t[0], f'from the array {name!r}'
            return fallback, f'the array {name!r} does not increase step by step; steps of {period} s assumed'
    return fallback, f'no time array; steps of {period} s assumed'
