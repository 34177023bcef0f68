"""Load a :class:`~robotarium_exp.analysis.trajectory.Trajectory` from whatever an experiment returned.

* a folder as downloaded from the Robotarium: the submission's ``vtube_t.npy`` and ``vtube_poses.npy``;
* our own ``.npz`` logs (``vtube simulate``, ``vtube robotarium run``, the bundled simulator's pose log);
* ROS1 ``.bag`` files and ROS2 bag folders (:mod:`robotarium_exp.analysis.bags`).

Arrays load without pickle. A truncated or corrupt file is reported by name, with what else could be read.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.analysis.bags import read_bag
from robotarium_exp.analysis.trajectory import Trajectory
from robotarium_exp.errors import AnalysisError
from vtube_planning.errors import LogError
from vtube_planning.swarm.log import read_log

SUBMISSION_PREFIX = 'vtube_'


def load_trajectory(inputs: list[str | Path], **bag_options: Any) -> Trajectory:
    """Dispatch on what ``inputs`` are (see the module docstring)."""
    paths = [Path(p) for p in inputs]
    if not paths:
        msg = 'no input given; pass a folder of .npy files, a .npz log, or ROS bags.'
        raise AnalysisError(msg)
    first = paths[0]
    if (first.is_dir() and (first / 'metadata.yaml').exists()) or first.suffix == '.bag':
        return read_bag(paths, **bag_options)
    if first.is_dir():
        return load_submission_folder(first)
    if first.suffix == '.npz':
        return load_npz_log(first)
    if not first.exists():
        msg = f'{str(first)!r} does not exist.'
        raise AnalysisError(msg)
    msg = f'cannot tell what {str(first)!r} is: expected a folder, a .npz log, a .bag file or a ROS2 bag folder.'
    raise AnalysisError(msg)


def load_submission_folder(folder: Path) -> Trajectory:
    """The arrays a submission saved (``vtube_t.npy``, ``vtube_poses.npy``), as downloaded from the testbed."""
    files = sorted(folder.glob(SUBMISSION_PREFIX + '*.npy'))
    if not files:
        msg = (
            f'{str(folder)!r} holds no {SUBMISSION_PREFIX}*.npy files; download the data files of the experiment '
            'into one folder.'
        )
        raise AnalysisError(msg)
    arrays, broken = {}, []
    for path in files:
        try:
            arrays[path.stem.removeprefix(SUBMISSION_PREFIX)] = np.load(path, allow_pickle=False)
        except (OSError, ValueError, EOFError) as err:
            broken.append(f'{path.name} ({err})')
    if 't' not in arrays or 'poses' not in arrays:
        read = sorted(arrays)
        msg = (
            f'{str(folder)!r}: cannot read vtube_t.npy and vtube_poses.npy; truncated or corrupt: {broken}; '
            f'read: {read}.'
        )
        raise AnalysisError(msg)
    steps = min(arrays['t'].shape[0], arrays['poses'].shape[0])  # a save interrupted between two files
    poses = arrays['poses'][:steps]
    return Trajectory(
        np.asarray(arrays['t'][:steps], dtype=float),
        poses[:, :2],
        poses[:, 2],
        tuple(f'robot_{k}' for k in range(poses.shape[2])),
        {
            'kind': 'robotarium submission',
            'path': str(folder),
            'unreadable': broken,
            'arrays': {k: list(v.shape) for k, v in arrays.items()},
        },
    )


def load_npz_log(path: Path) -> Trajectory:
    """Our logs (:mod:`vtube_planning.swarm.log`): simulations, Robotarium experiments, the bundled simulator's."""
    try:
        arrays, meta = read_log(path)
    except LogError as err:
        raise AnalysisError(str(err)) from err
    positions = arrays['positions_m']
    return Trajectory(
        np.asarray(arrays['t_s'], dtype=float),
        positions,
        arrays.get('headings_rad'),
        tuple(f'robot_{k}' for k in range(positions.shape[2])),
        {'kind': 'vtube log', 'path': str(path), 'scene': meta.get('scene'), 'planned': meta.get('planned')},
    )
