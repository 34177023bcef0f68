"""The one trajectory log of vtube, written so that a crash loses little (format: `vtube_planning.npzfile`).

Simulations (`vtube_planning.swarm.simulate`), Robotarium experiments (`robotarium_exp.experiment`),
the recorder of a run on a Robotarium class (`robotarium_exp.recorder`, ``rps_alias --log``) and the submitted file
(`submission.runtime`: one ``.npy`` per array and the metadata as JSON, read with `checked_log`) all
write this schema, and the
analysis reads it; it sits below every room of the house so that each may use it:

* arrays, one row per step: ``t_s`` (T,) and ``positions_m`` (T, 2, N), the robots' centres, always;
  ``headings_rad`` (T, N) for unicycles; whatever else the writer measured (commands, ``r_a_m``, ``l_m``, ...);
* metadata: ``format`` (``'vtube-trajectory'``), ``version`` (`LOG_VERSION`), ``kind`` (who wrote it),
  ``n_robots``, ``dt_s``, and at the end ``finished`` with the run's results.

A [`LogWriter`][vtube_planning.log.LogWriter] keeps the rows it has been given and rewrites the whole file every
``flush_every`` rows, atomically, under a partial name (``run.partial.npz`` for ``run.npz``) until the run is finished:
the file on disk is always a complete, readable ``.npz``, an interrupted run leaves every row up to its last flush in
the partial file, and a finished log of an earlier run at the same path is replaced only by a finished one.
[`read_log`][vtube_planning.log.read_log] reads this version and the earlier ones (version 1 logs held ``poses`` (T, 3,
N) instead of positions and headings), and names any other version it is given.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import LogError
from vtube_planning.npzfile import read_npz, write_npz

LOG_FORMAT = 'vtube-trajectory'
LOG_VERSION = 2
REQUIRED = ('t_s', 'positions_m')
_V1_FORMAT = 'vtube-trajectory-1'


class LogWriter:
    """Collects per-step arrays and rewrites the ``.npz`` log atomically every ``flush_every`` steps.

    Parameters
    ----------
    path
        The log file (``.npz``); its folder is created. None keeps the rows in memory only
        ([`arrays`][vtube_planning.log.LogWriter.arrays]).
    meta
        JSON-serialisable description of the run (``kind`` at least), stored with every flush.
    flush_every
        Steps between rewrites (>= 1).
    """

    def __init__(self, path: str | Path | None, meta: dict[str, Any], *, flush_every: int = 100) -> None:
        self.path = Path(path) if path is not None else None
        self.meta = dict(meta, format=LOG_FORMAT, version=LOG_VERSION)
        self.flush_every = max(1, int(flush_every))
        self._rows: dict[str, list[NDArray[Any]]] = {}
        self._pending = 0

    def append(self, **row: NDArray[Any] | float) -> None:
        """Add one step (every call gives the same keys, ``t_s`` and ``positions_m`` among them)."""
        if not self._rows:
            missing = [key for key in REQUIRED if key not in row]
            if missing:
                msg = f'a vtube trajectory log needs {list(REQUIRED)} in every row; this one lacks {missing}.'
                raise LogError(msg)
        for key, value in row.items():
            self._rows.setdefault(key, []).append(np.array(value, copy=True))
        self._pending += 1
        if self._pending >= self.flush_every:
            self.flush()

    def arrays(self) -> dict[str, NDArray[Any]]:
        """Every row so far, stacked: (T, ...) per key."""
        return {key: np.stack(values) for key, values in self._rows.items()}

    @property
    def partial_path(self) -> Path | None:
        """Where the log is written until it is finished."""
        return None if self.path is None else self.path.with_name(f'{self.path.stem}.partial{self.path.suffix}')

    def flush(self, **extra_meta: Any) -> Path | None:
        """Rewrite the log with every row so far (and extra metadata, e.g. final metrics): to
        [`partial_path`][vtube_planning.log.LogWriter.partial_path], or with ``finished=True`` to the log's path,
        removing the partial file. Returns the file written."""
        self.meta.update(extra_meta)
        self._pending = 0
        if self.path is None or self.partial_path is None:
            return None
        target = self.path if self.meta.get('finished') else self.partial_path
        write_npz(target, self.arrays(), self.meta)
        if target == self.path:
            self.partial_path.unlink(missing_ok=True)
        return target


def read_log(path: str | Path) -> tuple[dict[str, NDArray[Any]], dict[str, Any]]:
    """Arrays and metadata of a vtube trajectory log, in the current schema (older versions are upgraded)."""
    arrays, meta = read_npz(path, LogError, 'trajectory log')
    return checked_log(arrays, meta, path)


def checked_log(
    arrays: dict[str, NDArray[Any]], meta: dict[str, Any], path: str | Path
) -> tuple[dict[str, NDArray[Any]], dict[str, Any]]:
    """A log's arrays and metadata, however stored, checked against the schema (older versions upgraded); errors
    name ``path``."""
    if meta.get('format') == _V1_FORMAT:
        if 'poses' in arrays:
            poses = arrays.pop('poses')
            arrays['positions_m'], arrays['headings_rad'] = poses[:, :2], poses[:, 2]
        meta = dict(meta, format=LOG_FORMAT, version=1)
    elif meta.get('format') != LOG_FORMAT:
        msg = f'{str(path)!r} is not a vtube trajectory log (format {meta.get("format")!r}, expected {LOG_FORMAT!r}).'
        raise LogError(msg)
    elif meta.get('version') != LOG_VERSION:
        msg = (
            f'{str(path)!r} is a vtube trajectory log of version {meta.get("version")!r}; this vtube reads '
            f'versions 1 to {LOG_VERSION}. Read it with the vtube that wrote it, or upgrade vtube.'
        )
        raise LogError(msg)
    missing = [key for key in REQUIRED if key not in arrays]
    if missing:
        msg = f'{str(path)!r} is a vtube trajectory log without {missing} (it has {sorted(arrays)}).'
        raise LogError(msg)
    t_s, positions = arrays['t_s'], arrays['positions_m']
    if t_s.ndim != 1 or positions.ndim != 3 or positions.shape[:2] != (t_s.size, 2):
        msg = (
            f'{str(path)!r} is a damaged vtube trajectory log: t_s must be (T,) and positions_m (T, 2, N); got '
            f'{t_s.shape} and {positions.shape}.'
        )
        raise LogError(msg)
    return arrays, meta
