"""What a check reuses from an earlier one, keyed by a content hash: V2's initializer durations for a formation,
and the state V2's initialization leaves in a run.

The 200 runs of V2's initializer alone (`robotarium_exp.initializer`) that the duration to declare rests on depend
only on the file's initial conditions, the seeds, the step limit and the bundled simulator; not on the plan, the
controller or anything else the file flies. So a rebuild after a change of control parameters, a check of a file
built before, or the other scene of the same formation, takes them from a cache instead of running them again.

The key is the sha256 of everything they depend on: the initial conditions' float64 bytes, the step limit, the
source of every module of ``robotarium_exp`` the initializer imports, directly or through another
(`initializer_sources`: the simulator, its barrier QP and V2's draws; not the tube experiment's design, formation,
parking or flight, so that a change there keeps the cached durations) and the versions of Python, numpy, scipy and
cvxopt. One JSON file per key maps each seed run so far to its duration (``null``: stuck); the seeds asked for that
it lacks are run (`robotarium_exp.initializer.initializer_durations`) and added. The folder is ``$VTUBE_CACHE_DIR``
when set, else ``$XDG_CACHE_HOME/vtube``, else ``~/.cache/vtube``: never the repository. A file that does not read
back as such a map is ignored (run again and replaced). Each seed's duration is stored as its run ends, so an
interrupted check keeps the seeds it ran. The shipped scenes' formations come with their durations
(`SHIPPED`, made by `submission.shipped`): a first build of a shipped scene finds them there.

A check's runs of the file start with V2's initialization, the same for a seed under every testbed model and after
any change of the file's control (`robotarium_exp.rps.initialization_memo`): `InitializedStates` keeps the state it
leaves, one ``.npz`` per key (arrays only, read without pickle, checked field by field before use), under
``initialized/`` beside the durations, salted with the same sources and versions.
"""

from __future__ import annotations

import ast
import hashlib
import json
import os
import platform
from collections.abc import Callable, Iterable
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

import robotarium_exp
from robotarium_exp.initializer import INITIALIZATION_LIMIT, InitializerSample, initializer_durations
from robotarium_exp.rps.initialization_memo import State
from vtube_planning.files import write_atomically

CACHE_ENV = 'VTUBE_CACHE_DIR'
FOLDER = 'initializer'
STATES_FOLDER = 'initialized'
VERSIONED = ('numpy', 'scipy', 'cvxopt')
ROOT_MODULE = 'robotarium_exp.initializer'
"""Where the initializer's imports are followed from."""
SHIPPED = Path(__file__).with_name('shipped_initializer_durations.json')
"""The durations of the shipped scenes' formations, by the same keys (`submission.shipped`), read only."""


def cache_folder() -> Path:
    """Where the cache lives (module doc)."""
    own = os.environ.get(CACHE_ENV)
    if own:
        return Path(own)
    xdg = os.environ.get('XDG_CACHE_HOME')
    return (Path(xdg) if xdg else Path.home() / '.cache') / 'vtube'


def initializer_key(ic: NDArray[np.float64], limit: int) -> str:
    """The content hash the durations of ``ic`` (3xN) under ``limit`` steps are stored by."""
    digest = hashlib.sha256(simulator_salt())
    ic = np.ascontiguousarray(ic, dtype=np.float64)
    digest.update(f'{ic.shape} {limit}'.encode())
    digest.update(ic.tobytes())
    return digest.hexdigest()


def simulator_salt() -> bytes:
    """What V2's initialization depends on beyond its inputs: the versions of Python and the libraries, and the
    sources of `initializer_sources`."""
    digest = hashlib.sha256(platform.python_version().encode())
    for name in VERSIONED:
        digest.update(f' {name} {metadata.version(name)}'.encode())
    for name, source in initializer_sources():
        digest.update(name.encode() + b'\0' + source)
    return digest.digest()


class InitializedStates:
    """The states V2's initialization left, one ``.npz`` per key in ``folder`` (module doc); a
    `robotarium_exp.rps.initialization_memo.InitializationMemo`."""

    def __init__(self, folder: Path | None = None, salt: bytes | None = None) -> None:
        self.folder = (folder or cache_folder()) / STATES_FOLDER
        self.salt = simulator_salt() if salt is None else salt

    def recall(self, key: str) -> State | None:
        try:
            with np.load(self.folder / f'{key}.npz', allow_pickle=False) as stored:
                return {name: stored[name] for name in stored.files}
        except (OSError, ValueError, EOFError):
            return None

    def keep(self, key: str, state: State) -> None:
        """Store ``state``; a cache that cannot be written only costs the next run its initialization."""
        arrays: dict[str, Any] = dict(state)
        try:
            write_atomically(self.folder / f'{key}.npz', lambda handle: np.savez(handle, **arrays))
        except OSError:
            return


def initializer_sources() -> list[tuple[str, bytes]]:
    """The sources the initializer's runs may depend on, (path in ``robotarium_exp``, bytes) in order: `ROOT_MODULE`
    and every module of ``robotarium_exp`` it imports, directly or through another, anywhere in a module (in functions
    too; not under ``if TYPE_CHECKING``), with the packages' ``__init__`` files on the way."""
    root = Path(robotarium_exp.__file__).parent
    todo, found = [ROOT_MODULE], set()
    while todo:
        name = todo.pop()
        parts = name.split('.')[1:]
        for path in (root.joinpath(*parts).with_suffix('.py'), root.joinpath(*parts, '__init__.py')):
            if path.is_file() and path not in found:
                found.add(path)
                todo += [module for module in _imported(path) if module.split('.')[0] == 'robotarium_exp']
        todo += ['.'.join(['robotarium_exp', *parts[:k]]) for k in range(len(parts))]  # the packages on the way
    return [(path.relative_to(root).as_posix(), path.read_bytes()) for path in sorted(found)]


def _imported(path: Path) -> set[str]:
    """The modules a source file imports, and for ``from M import a``, also ``M.a`` (it may be a module)."""
    tree = ast.parse(path.read_bytes())
    typing_only = {
        id(inner)
        for node in ast.walk(tree)
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == 'TYPE_CHECKING'
        for inner in ast.walk(node)
    }
    names: set[str] = set()
    for node in (node for node in ast.walk(tree) if id(node) not in typing_only):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names |= {node.module} | {f'{node.module}.{alias.name}' for alias in node.names}
        elif isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
    return names


def cached_initializer_durations(
    ic: NDArray[np.float64],
    seeds: Iterable[int],
    limit: int = INITIALIZATION_LIMIT,
    *,
    seed_done: Callable[[], None] | None = None,
    folder: Path | None = None,
) -> InitializerSample:
    """`robotarium_exp.initializer.initializer_durations` of ``ic`` over ``seeds``, the seeds run before for the
    same key taken from the cache in ``folder`` (default `cache_folder`) or, for a shipped scene's formation, from
    `SHIPPED`; the others run and added to the cache as each ends (an interrupted check keeps them)."""
    seeds = list(seeds)
    key = initializer_key(ic, limit)
    path = (folder or cache_folder()) / FOLDER / f'{key}.json'
    known = {**shipped_durations().get(key, {}), **_read(path)}
    missing = [seed for seed in dict.fromkeys(seeds) if seed not in known]
    for _ in range(len(seeds) - len(missing)):
        (seed_done or (lambda: None))()
    if missing:

        def keep(seed: int, duration: float | None) -> None:
            known[seed] = duration
            _write(path, known)

        initializer_durations(ic, missing, limit, seed_done=seed_done, ran=keep)
    done = tuple(d for d in (known[seed] for seed in seeds) if d is not None)
    return InitializerSample(done, tuple(seed for seed in seeds if known[seed] is None))


def shipped_durations() -> dict[str, dict[int, float | None]]:
    """The durations `SHIPPED` holds, by key ({} when it is absent or not such a file)."""
    try:
        stored = json.loads(SHIPPED.read_text(encoding='utf-8'))
        return {entry['key']: _durations(entry) for entry in stored['formations']}
    except (OSError, ValueError, TypeError, KeyError, AttributeError):
        return {}


def _read(path: Path) -> dict[int, float | None]:
    """The seeds' durations stored at ``path`` ({} when there is none, or it is not such a map)."""
    try:
        return _durations(json.loads(path.read_text(encoding='utf-8')))
    except (OSError, ValueError, TypeError, KeyError, AttributeError):
        return {}


def _durations(stored: dict[str, Any]) -> dict[int, float | None]:
    """A stored map's seeds and durations (null: stuck)."""
    return {int(seed): None if d is None else float(d) for seed, d in stored['durations_s'].items()}


def _write(path: Path, known: dict[int, float | None]) -> None:
    """Store the durations; a cache that cannot be written only costs the next check the runs."""
    text = json.dumps({'durations_s': {str(seed): known[seed] for seed in sorted(known)}})
    try:
        write_atomically(path, text)
    except OSError:
        return
