"""What a check reuses from an earlier one: V2's initializer durations for a formation, keyed by a content hash.

The 200 runs of V2's initializer alone (`robotarium_exp.initializer`) that the duration to declare rests on depend
only on the file's initial conditions, the seeds, the step limit and the bundled simulator; not on the plan, the
controller or anything else the file flies. So a rebuild after a change of control parameters, a check of a file
built before, or the other scene of the same formation, takes them from a cache instead of running them again.

The key is the sha256 of everything they depend on: the initial conditions' float64 bytes, the step limit, the
source of every module of ``robotarium_exp`` but the tube experiment's own (`EXPERIMENT_SIDE`: the simulator, its
barrier QP and V2's draws are in it) and the versions of Python, numpy, scipy and cvxopt. One JSON file per key maps
each seed run so far to its duration (``null``: stuck); the seeds asked for that it lacks are run
(`robotarium_exp.initializer.initializer_durations`) and added. The folder is ``$VTUBE_CACHE_DIR`` when set, else
``$XDG_CACHE_HOME/vtube``, else ``~/.cache/vtube``: never the repository. A file that does not read back as such a
map is ignored (run again and replaced).
"""

from __future__ import annotations

import hashlib
import json
import os
import platform
from collections.abc import Callable, Iterable
from importlib import metadata
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

import robotarium_exp
from robotarium_exp.initializer import INITIALIZATION_LIMIT, InitializerSample, initializer_durations
from vtube_planning.files import write_atomically

CACHE_ENV = 'VTUBE_CACHE_DIR'
FOLDER = 'initializer'
VERSIONED = ('numpy', 'scipy', 'cvxopt')
EXPERIMENT_SIDE = frozenset(
    ('analysis', 'compare.py', 'design.py', 'experiment.py', 'fit.py', 'flight.py', 'flight_data.py', 'plots.py')
    + ('safety.py', 'scene.py', 'tracking.py', 'verdict.py', 'verifier.py')
)
"""The tube experiment's modules (its controller, safety filter, design, verdicts and analysis), which V2's
initializer never runs (a test runs it and looks): a change to them keeps the cached durations. Every other module
of ``robotarium_exp`` (the simulators, their QPs, V2's draws, and any new one) is in the key."""


def cache_folder() -> Path:
    """Where the cache lives (module doc)."""
    own = os.environ.get(CACHE_ENV)
    if own:
        return Path(own)
    xdg = os.environ.get('XDG_CACHE_HOME')
    return (Path(xdg) if xdg else Path.home() / '.cache') / 'vtube'


def initializer_key(ic: NDArray[np.float64], limit: int) -> str:
    """The content hash the durations of ``ic`` (3xN) under ``limit`` steps are stored by."""
    digest = hashlib.sha256()
    ic = np.ascontiguousarray(ic, dtype=np.float64)
    digest.update(f'{ic.shape} {limit} {platform.python_version()}'.encode())
    for name in VERSIONED:
        digest.update(f' {name} {metadata.version(name)}'.encode())
    digest.update(ic.tobytes())
    for name, source in initializer_sources():
        digest.update(name.encode() + b'\0' + source)
    return digest.hexdigest()


def initializer_sources() -> list[tuple[str, bytes]]:
    """The sources the initializer's runs may depend on, (path in ``robotarium_exp``, bytes) in order: every module
    of the package but the tube experiment's own (`EXPERIMENT_SIDE`)."""
    root = Path(robotarium_exp.__file__).parent
    found = []
    for path in sorted(root.rglob('*.py')):
        name = path.relative_to(root).as_posix()
        if name.split('/')[0] not in EXPERIMENT_SIDE:
            found.append((name, path.read_bytes()))
    return found


def cached_initializer_durations(
    ic: NDArray[np.float64],
    seeds: Iterable[int],
    limit: int = INITIALIZATION_LIMIT,
    *,
    seed_done: Callable[[], None] | None = None,
    folder: Path | None = None,
) -> InitializerSample:
    """`robotarium_exp.initializer.initializer_durations` of ``ic`` over ``seeds``, the seeds run before for the
    same key taken from the cache in ``folder`` (default `cache_folder`), the others run and added to it."""
    seeds = list(seeds)
    path = (folder or cache_folder()) / FOLDER / f'{initializer_key(ic, limit)}.json'
    known = _read(path)
    missing = [seed for seed in dict.fromkeys(seeds) if seed not in known]
    for _ in range(len(seeds) - len(missing)):
        (seed_done or (lambda: None))()
    if missing:
        ran = initializer_durations(ic, missing, limit, seed_done=seed_done)
        durations = iter(ran.durations_s)
        known.update({seed: None if seed in ran.stuck_seeds else next(durations) for seed in missing})
        _write(path, known)
    done = tuple(d for d in (known[seed] for seed in seeds) if d is not None)
    return InitializerSample(done, tuple(seed for seed in seeds if known[seed] is None))


def _read(path: Path) -> dict[int, float | None]:
    """The seeds' durations stored at ``path`` ({} when there is none, or it is not such a map)."""
    try:
        stored = json.loads(path.read_text(encoding='utf-8'))
        found = {int(seed): None if d is None else float(d) for seed, d in stored['durations_s'].items()}
    except (OSError, ValueError, TypeError, KeyError, AttributeError):
        return {}
    return found


def _write(path: Path, known: dict[int, float | None]) -> None:
    """Store the durations; a cache that cannot be written only costs the next check the runs."""
    text = json.dumps({'durations_s': {str(seed): known[seed] for seed in sorted(known)}})
    try:
        write_atomically(path, text)
    except OSError:
        return
