"""Trajectory logs: ``.npz`` files of plain arrays plus one JSON string, written so that a crash loses little.

A :class:`LogWriter` keeps the rows it has been given and rewrites the whole file every ``flush_every`` rows,
into a temporary file that then replaces the log atomically. The log on disk is therefore always a complete,
readable ``.npz``: an interrupted run leaves every row up to its last flush. Files load without pickle.
"""

from __future__ import annotations

import json
import os
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import LogError

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
        self.path.parent.mkdir(parents=True, exist_ok=True)
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
        arrays = {key: np.stack(values) for key, values in self._rows.items()}
        tmp = self.path.with_name(self.path.name + '.tmp')
        with tmp.open('wb') as fh:
            np.savez(fh, meta=np.array(json.dumps(self.meta)), **arrays)
        os.replace(tmp, self.path)
        self._pending = 0
        return self.path


def read_log(path: str | Path) -> tuple[dict[str, NDArray[Any]], dict[str, Any]]:
    """Arrays and metadata of a log written by :class:`LogWriter`."""
    path = Path(path)
    try:
        with path.open('rb') as fh, np.load(fh, allow_pickle=False) as data:
            arrays = {key: data[key] for key in data.files}
        meta = json.loads(str(arrays.pop('meta')))
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as err:
        msg = f'cannot read trajectory log {str(path)!r}: {err}.'
        raise LogError(msg) from err
    if meta.get('format') != LOG_FORMAT:
        msg = f'{str(path)!r} is not a vtube trajectory log (format {meta.get("format")!r}, expected {LOG_FORMAT!r}).'
        raise LogError(msg)
    return arrays, meta
