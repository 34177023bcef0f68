"""Load a [`Trajectory`][robotarium_exp.analysis.trajectory.Trajectory] from whatever an experiment returned.

* a folder as downloaded from the Robotarium: the submission's trajectory log (``vtube_meta.json`` and
  ``vtube_t_s.npy``, ``vtube_positions_m.npy``, ...), or the bare ``vtube_t.npy`` and ``vtube_poses.npy`` of
  earlier files;
* a ``.mat`` file a MATLAB script saved on the Robotarium (`robotarium_exp.analysis.matfiles`);
* our own ``.npz`` logs (``vtube simulate``, ``vtube robotarium run``, the bundled simulator's pose log);
* ROS1 ``.bag`` files, ROS2 bag folders, bare ``.mcap`` / ``.db3`` files and folders of them without
  ``metadata.yaml`` (`robotarium_exp.analysis.bags`).

Arrays load without pickle. A truncated or corrupt file is reported by name, with what else could be read. Every
loader records the files it read (`input_record` gives their sizes and hashes).
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.analysis.bags import read_bag
from robotarium_exp.analysis.matfiles import read_mat
from robotarium_exp.analysis.passage import FlightStart
from robotarium_exp.analysis.trajectory import (
    DEFAULT_MAX_GAP,
    MaxGap,
    RobotSamples,
    Trajectory,
    assemble,
    seconds_to_ns,
)
from robotarium_exp.errors import AnalysisError
from vtube_planning.errors import LogError
from vtube_planning.log import REQUIRED as LOG_REQUIRED
from vtube_planning.log import checked_log, read_log
from vtube_planning.npzfile import why

SUBMISSION_PREFIX = 'vtube_'
SUBMISSION_META = 'vtube_meta.json'
ROS2_STORAGE = ('.mcap', '.db3')
ACCEPTED = (
    'a folder of vtube_*.npy files, a .npz log, a .mat file, .bag files, a ROS2 bag folder, or .mcap / .db3 files'
)


def load_trajectory(inputs: list[str | Path], *, max_gap: MaxGap = DEFAULT_MAX_GAP, **bag_options: Any) -> Trajectory:
    """Dispatch on what ``inputs`` are (see the module docstring); ``bag_options`` go to
    [`read_bag`][robotarium_exp.analysis.bags.read_bag]."""
    paths = [Path(p) for p in inputs]
    if not paths:
        msg = f'no input given; pass {ACCEPTED}.'
        raise AnalysisError(msg)
    for path in paths:
        if not path.exists():
            msg = f'{str(path)!r} does not exist.'
            raise AnalysisError(msg)
    bags = [bag for path in paths for bag in _bags_in(path)]
    first = paths[0]
    if bags:
        if len(bags) < len(paths) and len(paths) > 1:
            msg = f'{[str(p) for p in paths]}: give either ROS bags or one other input, not both.'
            raise AnalysisError(msg)
        contents = read_bag(bags, **bag_options)
        files = [f for bag in bags for f in ([bag] if bag.is_file() else sorted(bag.iterdir()))]
        source = {
            'kind': 'ros bag',
            'path': str(first),
            'files': [str(f) for f in files],
            'topics': contents.topics,
            'world_frame': contents.world_frame,
            'ignored': contents.ignored,
            **_recorded_run(contents.custom, str(first)),
        }
        return assemble(contents.samples, source=source, max_gap=max_gap)
    if len(paths) > 1:
        msg = f'several inputs are read together only when they are ROS bags; analyse {str(first)!r} on its own.'
        raise AnalysisError(msg)
    if first.is_dir():
        samples, source = load_submission_folder(first)
    elif first.suffix == '.npz':
        samples, source = load_npz_log(first)
    elif first.suffix == '.mat':
        t_s, poses, details = read_mat(first)
        samples = _per_robot(t_s, poses)
        source = {'kind': 'robotarium .mat', 'path': str(first), 'files': [str(first)], **details}
    else:
        msg = f'cannot tell what {str(first)!r} is: expected {ACCEPTED}.'
        raise AnalysisError(msg)
    return assemble(samples, source=source, max_gap=max_gap)


def _bags_in(path: Path) -> list[Path]:
    """The bags ``path`` stands for: itself (a .bag, .mcap or .db3 file, a folder with metadata.yaml), or the
    storage files of a folder without metadata.yaml that holds no submission files."""
    if path.is_file():
        return [path] if path.suffix in ('.bag', *ROS2_STORAGE) else []
    if (path / 'metadata.yaml').exists():
        return [path]
    if any(path.glob(SUBMISSION_PREFIX + '*.npy')):
        return []
    return sorted(f for f in path.iterdir() if f.suffix in ('.bag', *ROS2_STORAGE))


@dataclass(frozen=True)
class InputFile:
    """A file an analysis read: its path, size and SHA-256."""

    path: str
    size_bytes: int
    sha256: str

    def to_json(self) -> dict[str, str | int]:
        return {'path': self.path, 'bytes': self.size_bytes, 'sha256': self.sha256}


def input_record(files: list[str]) -> tuple[InputFile, ...]:
    """Path, size and SHA-256 of each file read."""
    record = []
    for name in files:
        digest = hashlib.sha256()
        with Path(name).open('rb') as stream:
            for block in iter(lambda: stream.read(1 << 20), b''):
                digest.update(block)
        record.append(InputFile(name, Path(name).stat().st_size, digest.hexdigest()))
    return tuple(record)


def _per_robot(t_s: np.ndarray, poses: np.ndarray, where: str = 'the time stamps') -> dict[str, RobotSamples]:
    """Poses (T, 3, N) on stamps in seconds (T,) (read from ``where``) -> each robot's samples."""
    stamps = seconds_to_ns(t_s, where)
    return {f'robot_{k}': RobotSamples(stamps, poses[:, :2, k], poses[:, 2, k]) for k in range(poses.shape[2])}


def load_submission_folder(folder: Path) -> tuple[dict[str, RobotSamples], dict[str, Any]]:
    """What a submission saved, as downloaded from the testbed: its trajectory log (``vtube_meta.json`` and one
    ``vtube_NAME.npy`` per array), or the bare ``vtube_t.npy`` and ``vtube_poses.npy`` (T, 3, N) of earlier files."""
    files = sorted(folder.glob(SUBMISSION_PREFIX + '*.npy'))
    if not files:
        held = sorted(f.name for f in folder.iterdir())[:10]
        msg = (
            f'{str(folder)!r} holds no {SUBMISSION_PREFIX}*.npy files and no bag (it holds {held}); pass the folder '
            f"the experiment's data files were downloaded into, or one file: {ACCEPTED}."
        )
        raise AnalysisError(msg)
    arrays, broken, cut = {}, [], []
    for path in files:
        try:
            loaded = np.load(path, allow_pickle=False)
        except (OSError, ValueError, EOFError) as err:
            loaded = _frames_before_the_cut(path)
            if loaded is None:
                broken.append(f'{path.name} ({why(err)})')
                continue
            cut.append(f'{path.name}: cut in a save after {loaded.shape[0]} whole frames; those are analysed')
        if not isinstance(loaded, np.ndarray) or not (
            np.issubdtype(loaded.dtype, np.number) or np.issubdtype(loaded.dtype, np.bool_)
        ):
            what = 'an archive of arrays' if not isinstance(loaded, np.ndarray) else f'{loaded.dtype} values'
            broken.append(f'{path.name} (holds {what}, not one array of numbers)')
            continue
        arrays[path.stem.removeprefix(SUBMISSION_PREFIX)] = loaded
    source = {
        'kind': 'robotarium submission',
        'path': str(folder),
        'unreadable': broken,
        'cut': cut,
        'arrays': {k: list(v.shape) for k, v in arrays.items()},
    }
    if (folder / SUBMISSION_META).is_file():
        return _submission_log(folder, arrays, broken, source)
    if 't' not in arrays or 'poses' not in arrays:
        missing = [
            f'{SUBMISSION_PREFIX}{n}.npy'
            for n in ('t', 'poses')
            if not (folder / f'{SUBMISSION_PREFIX}{n}.npy').exists()
        ]
        lacking = f'it holds no {" and no ".join(missing)}' if missing else f'truncated or corrupt: {"; ".join(broken)}'
        msg = (
            f'{str(folder)!r}: cannot read vtube_t.npy and vtube_poses.npy ({lacking}; read: {sorted(arrays) or "nothing"}); '
            'give the folder the testbed returned, with the files the submission saved.'
        )
        raise AnalysisError(msg)
    t_s, poses = arrays['t'], arrays['poses']
    if t_s.ndim != 1 or poses.ndim != 3 or poses.shape[1] != 3 or not np.issubdtype(poses.dtype, np.number):
        msg = (
            f'{str(folder)!r}: vtube_t.npy must hold the times (T,) and vtube_poses.npy the poses (T, 3, N) of numbers, '
            f'as the submission saves them; got {t_s.dtype} {t_s.shape} and {poses.dtype} {poses.shape}.'
        )
        raise AnalysisError(msg)
    steps = min(t_s.shape[0], poses.shape[0])  # a save interrupted between two files
    source['files'] = [str(folder / f'{SUBMISSION_PREFIX}{name}.npy') for name in ('t', 'poses')]
    t_s = np.asarray(arrays['t'][:steps], dtype=float)
    return _per_robot(t_s, arrays['poses'][:steps], f'{str(folder)!r}: vtube_t.npy'), source


def _frames_before_the_cut(path: Path) -> np.ndarray | None:
    """The whole frames (rows of the first axis) of a ``.npy`` file of numbers cut in the middle of a save (the
    testbed may stop a run at any time), or None when its header is unreadable or not one frame is whole."""
    try:
        with path.open('rb') as stream:
            version = np.lib.format.read_magic(stream)
            header = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
            shape, fortran, dtype = header(stream)
            data = stream.read()
    except (OSError, ValueError, EOFError):
        return None
    if fortran or not shape or dtype.hasobject or not np.issubdtype(dtype, np.number):
        return None
    frame_bytes = dtype.itemsize * math.prod(shape[1:])
    frames = min(shape[0], len(data) // frame_bytes) if frame_bytes else 0
    if frames < 1:
        return None
    return np.frombuffer(data[: frames * frame_bytes], dtype=dtype).reshape((frames, *shape[1:]))


def _submission_log(
    folder: Path, arrays: dict[str, np.ndarray], broken: list[str], source: dict[str, Any]
) -> tuple[dict[str, RobotSamples], dict[str, Any]]:
    """A submission's trajectory log: its arrays cut to the steps every one of them holds (a save can be
    interrupted between two files), checked like any vtube log."""
    meta_path = folder / SUBMISSION_META
    try:
        meta = json.loads(meta_path.read_text(encoding='utf-8'))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
        msg = f'{str(meta_path)!r} is not readable JSON ({err}); the log it describes cannot be read without it.'
        raise AnalysisError(msg) from err
    if not isinstance(meta, dict):
        msg = f'{str(meta_path)!r} holds a JSON {type(meta).__name__}, not the object a submission writes there.'
        raise AnalysisError(msg)
    missing = [key for key in LOG_REQUIRED if key not in arrays]
    if missing:
        msg = f'{str(folder)!r}: cannot read {[SUBMISSION_PREFIX + k + ".npy" for k in missing]}; truncated or corrupt: {broken}.'
        raise AnalysisError(msg)
    steps = min(value.shape[0] if value.ndim else 0 for value in arrays.values())
    try:
        log, meta = checked_log({k: v[:steps] for k, v in arrays.items()}, meta, folder)
    except LogError as err:
        raise AnalysisError(str(err)) from err
    source['files'] = [str(meta_path)] + [str(folder / f'{SUBMISSION_PREFIX}{name}.npy') for name in sorted(arrays)]
    return _log_samples(log), source | _log_source(log, meta, str(meta_path))


def load_npz_log(path: Path) -> tuple[dict[str, RobotSamples], dict[str, Any]]:
    """Our logs (`vtube_planning.log`): simulations, Robotarium experiments, the bundled simulator's."""
    try:
        arrays, meta = read_log(path)
    except LogError as err:
        raise AnalysisError(str(err)) from err
    source = {'kind': 'vtube log', 'path': str(path), 'files': [str(path)]}
    return _log_samples(arrays), source | _log_source(arrays, meta, str(path))


def _log_source(arrays: dict[str, np.ndarray], meta: dict[str, Any], where: str) -> dict[str, Any]:
    """What a vtube log's description says of its run: scene, tube, plan, and where the flight began when it
    recorded that (`FlightStart`, on the trajectory's clock; a simulation's first row, whose robots are points
    (``point_robots``); None for logs that do not record it: earlier submissions)."""
    t_s = arrays['t_s']
    first = float(t_s[0]) if t_s.size else 0.0
    start = FlightStart.from_record(meta.get('flight_start'), where, first)
    simulated = meta.get('kind') == 'simulation' and start is None
    if simulated:  # a simulation starts at its first row, as `simulate` times it; its robots are points
        start = FlightStart(0, 0.0, 0.0)
    return {
        'scene': meta.get('scene'),
        'tube_hash': meta.get('tube_hash'),
        'planned': meta.get('planned'),
        'flight_start': start.to_record() if start is not None else None,
        'point_robots': simulated,
    }


def _recorded_run(custom: dict[str, str], where: str) -> dict[str, Any]:
    """What a bag `vtube export` wrote keeps of its log's run (`robotarium_exp.analysis.export.RECORDED`, JSON in
    its ``custom_data``): scene, tube, flight start; empty for any other bag."""
    from robotarium_exp.analysis.export import CUSTOM_KEY, RECORDED

    if CUSTOM_KEY not in custom:
        return {}
    try:
        recorded = json.loads(custom[CUSTOM_KEY])
    except ValueError as err:
        msg = f'{where}: its custom_data {CUSTOM_KEY!r} is not the JSON vtube export writes ({err}); remove the key.'
        raise AnalysisError(msg) from err
    if not isinstance(recorded, dict):
        msg = f'{where}: its custom_data {CUSTOM_KEY!r} holds a JSON {type(recorded).__name__}, not an object.'
        raise AnalysisError(msg)
    start = FlightStart.from_record(recorded.get('flight_start'), where)
    kept = {key: recorded.get(key) for key in RECORDED}
    return kept | {'flight_start': start.to_record() if start is not None else None}


def _log_samples(arrays: dict[str, np.ndarray]) -> dict[str, RobotSamples]:
    """Each robot's samples of a vtube trajectory log's arrays."""
    positions = arrays['positions_m']
    headings = arrays.get('headings_rad')
    stamps = seconds_to_ns(arrays['t_s'])
    return {
        f'robot_{k}': RobotSamples(stamps, positions[:, :, k], None if headings is None else headings[:, k])
        for k in range(positions.shape[2])
    }
