"""Trajectory logs, written so that a crash loses little (format: :mod:`vtube_planning.npzfile`).

A :class:`LogWriter` keeps the rows it has been given and rewrites the whole file every ``flush_every`` rows,
atomically. The log on disk is therefore always a complete, readable ``.npz``: an interrupted run leaves every
row up to its last flush.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import LogError
from vtube_planning.npzfile import read_npz, write_npz

LOG_FORMAT = 'vtube-trajectory-1'


class LogWriter:
    """Collects per-step arrays and rewrites the ``.npz`` log atomically every ``flush_every`` steps.

    Parameters
    ----------
    path
        The log file (``.npz``); its folder is created.
    meta
        JSON-serialisable description of the run, stored with every flush.
    flush_every
        Steps between rewrites (>= 1).
    """

    def __init__(self, path: str | Path, meta: dict[str, Any], *, flush_every: int = 100) -> None:
        self.path = Path(path)
        self.meta = dict(meta, format=LOG_FORMAT)
        self.flush_every = max(1, int(flush_every))
        self._rows: dict[str, list[NDArray[Any]]] = {}
        self._pending = 0

    def append(self, **row: NDArray[Any] | float) -> None:
        """Add one step (every call must give the same keys)."""
        for key, value in row.items():
            self._rows.setdefault(key, []).append(np.asarray(value))
        self._pending += 1
        if self._pending >= self.flush_every:
            self.flush()

    def flush(self, **extra_meta: Any) -> Path:
        """Rewrite the log with every row so far (and extra metadata, e.g. final metrics)."""
        self.meta.update(extra_meta)
        write_npz(self.path, {key: np.stack(values) for key, values in self._rows.items()}, self.meta)
        self._pending = 0
        return self.path


def read_log(path: str | Path) -> tuple[dict[str, NDArray[Any]], dict[str, Any]]:
    """Arrays and metadata of a log written by :class:`LogWriter`."""
    arrays, meta = read_npz(path, LogError, 'trajectory log')
    if meta.get('format') != LOG_FORMAT:
        msg = f'{str(path)!r} is not a vtube trajectory log (format {meta.get("format")!r}, expected {LOG_FORMAT!r}).'
        raise LogError(msg)
    return arrays, meta
