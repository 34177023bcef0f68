"""Real Robotarium runs with their commands, read from the ``.mat`` files their users published.

Shared by ``benchmarks/testbed_identification.py`` and ``benchmarks/testbed_replay.py``. Two layouts:

* plain arrays ``pose_data`` (3, N, T) and ``input_data`` (2, N, T) (``robotarium-lines3``, open loop);
* MATLAB class objects (a ``DataSaver`` with properties ``x_data`` (3, N, T) and ``u_data`` (2, N, T):
  yemam3/robustCBFs-GP, ``robotarium-cbf4`` and the runs of its history). scipy cannot read objects, but their
  values sit in the file's ``__function_workspace__``: a MAT stream whose one variable holds the objects' cells
  (``MCOS``); cell 0 is the metadata (property names and, per object, property -> cell), the values follow. This
  module reads just enough of that (the layout of MATLAB's version 3 metadata) to find ``x_data`` and ``u_data``.

In both, the pose at index k is what ``get_poses`` returned at iteration k and the command at index k is what
``set_velocities`` received in the same iteration (``main_robotarium_2.m``: ``x = r.get_poses()`` ...
``r.set_velocities(1:N, dxu)``; ``data_saver.save(x, dxu, ...)``).
"""

from __future__ import annotations

import io
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from tests.support.realdata import realdata_folder

DT = 0.033
"""The testbed's period per iteration, s."""
CELL_OFFSET = 2
"""A property's value index in the metadata counts from the third cell (MATLAB's version 3 layout)."""


@dataclass(frozen=True)
class Run:
    """One real run: poses (T, 3, N) as handed out and commands (T, 2, N) as sent, iteration by iteration."""

    name: str
    poses: np.ndarray
    commands: np.ndarray


def default_files(more: Path | None) -> list[Path]:
    """The runs beside the project (``robotarium-cbf4``, ``robotarium-lines3``) and the ``.mat`` files in ``more``."""
    files: list[Path] = []
    folder = realdata_folder()
    if folder is not None:
        files += sorted((folder / 'robotarium-cbf4').glob('*.mat')) + sorted(
            (folder / 'robotarium-lines3').glob('*.mat')
        )
    if more is not None:
        files += sorted(more.glob('*.mat'))
    return files


def load_runs(files: list[Path]) -> list[Run]:
    """The runs in ``files`` that hold poses and commands, each once: a run whose poses are the start of another's
    (the same run saved earlier, e.g. ``robotarium_data.mat`` at 4800 steps beside ``robotarium2_data.mat`` at
    5000) gives way to the longer."""
    runs: list[Run] = []
    for path in files:
        run = read_run(path)
        if run is None or run.poses.shape[0] <= 100:
            continue
        same = [k for k, kept in enumerate(runs) if _one_starts_the_other(run.poses, kept.poses)]
        if not same:
            runs.append(run)
        elif len(run.poses) > len(runs[same[0]].poses):
            runs[same[0]] = run
    return runs


def _one_starts_the_other(a: np.ndarray, b: np.ndarray) -> bool:
    t = min(len(a), len(b))
    return a.shape[1:] == b.shape[1:] and np.array_equal(a[:t], b[:t])


def read_run(path: Path) -> Run | None:
    """The run in ``path``, or None when it holds no poses with commands."""
    import scipy.io
    from scipy.io.matlab import MatReadWarning

    with warnings.catch_warnings():
        warnings.simplefilter('ignore', MatReadWarning)
        variables = scipy.io.loadmat(path)
    if 'pose_data' in variables and 'input_data' in variables:
        poses, commands = variables['pose_data'], variables['input_data']
    elif '__function_workspace__' in variables:
        values = object_properties(variables['__function_workspace__'].tobytes())
        if 'x_data' not in values or 'u_data' not in values:
            return None
        poses, commands = values['x_data'], values['u_data']
    else:
        return None
    poses, commands = np.asarray(poses, dtype=float), np.asarray(commands, dtype=float)
    if poses.ndim == 2:  # one robot: MATLAB dropped the trailing axis of (3, 1, T)? keep (3, N, T)
        poses, commands = poses[:, None, :], commands[:, None, :]
    return Run(path.stem, poses.transpose(2, 0, 1), commands.transpose(2, 0, 1))


def object_properties(workspace: bytes, wanted: tuple[str, ...] = ('x_data', 'u_data')) -> dict[str, np.ndarray]:
    """The ``wanted`` properties (3-D numeric arrays) of the objects in a ``__function_workspace__``, by name.

    A property is a triple (name index + 1, 1, value index) in the metadata's property blocks; the first triple of a
    wanted name whose value is a 3-D float array wins.
    """
    from scipy.io.matlab._mio5 import MatFile5Reader

    header = b'MATLAB 5.0 MAT-file'.ljust(116, b' ') + bytes(8) + b'\x00\x01IM'
    reader = MatFile5Reader(io.BytesIO(header + workspace[8:]), squeeze_me=False, struct_as_record=True)
    reader.initialize_read()
    reader.mat_stream.seek(128)
    var_header, _ = reader.read_var_header()
    cells = reader.read_var_array(var_header, process=True)[0, 0]['MCOS'][0]['arr'].ravel()
    meta = cells[0].ravel().tobytes()
    words = np.frombuffer(meta, '<u4')
    n_names, offsets = int(words[1]), words[2:10]
    names = [b.decode('latin-1') for b in meta[40 : offsets[0]].split(b'\x00')[:n_names]]
    props = np.frombuffer(meta[offsets[1] : offsets[4]], '<u4')
    values: dict[str, np.ndarray] = {}
    for name in wanted:
        if name not in names:
            continue
        for i in np.flatnonzero(props[:-2] == names.index(name) + 1):
            index = int(props[i + 2]) + CELL_OFFSET
            cell = cells[index] if props[i + 1] == 1 and index < cells.size else None
            if isinstance(cell, np.ndarray) and cell.dtype.kind == 'f' and cell.ndim == 3:
                values[name] = cell
                break
    return values


def clipped(commands: np.ndarray) -> np.ndarray:
    """The commands (T, 2, N) after the testbed's per-wheel clipping (``ARobotarium._threshold``)."""
    from robotarium_exp.rps.robotarium_abc import ARobotarium

    r, length, limit = ARobotarium.WHEEL_RADIUS, ARobotarium.BASE_LENGTH, ARobotarium.MAX_WHEEL_VELOCITY
    left = np.clip((2 * commands[:, 0] - length * commands[:, 1]) / (2 * r), -limit, limit)
    right = np.clip((2 * commands[:, 0] + length * commands[:, 1]) / (2 * r), -limit, limit)
    return np.stack([r / 2 * (left + right), r / length * (right - left)], axis=1)
