"""The package's file format: an ``.npz`` of plain arrays plus one JSON string, written atomically, read without pickle.

Plans and trajectory logs are stored this way. Writing goes to a temporary file that then replaces the target, so
the file on disk is always complete; reading never unpickles (a returned data file cannot run code).
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vtube_planning.files import write_atomically

META_KEY = 'meta'


def write_npz(path: str | Path, arrays: dict[str, NDArray[Any]], meta: dict[str, Any]) -> Path:
    """Write arrays and JSON metadata to ``path`` atomically (`write_atomically`)."""
    # the ** dicts are typed loosely because mypy also matches them against savez's allow_pickle: bool
    meta_member: dict[str, Any] = {META_KEY: np.array(json.dumps(meta))}
    array_members: dict[str, Any] = arrays
    return write_atomically(path, lambda handle: np.savez(handle, **meta_member, **array_members))


def read_npz(path: str | Path, error: type[Exception], what: str) -> tuple[dict[str, NDArray[Any]], dict[str, Any]]:
    """Arrays and metadata of a file written by `write_npz`; ``error`` (naming ``what``) if unreadable."""
    path = Path(path)
    hint = f'give a {what} as vtube writes it (.npz)'
    try:
        with path.open('rb') as fh:
            loaded = np.load(fh, allow_pickle=False)
            bare = not isinstance(loaded, np.lib.npyio.NpzFile)
            if not bare:
                with loaded as data:
                    arrays = {key: data[key] for key in data.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as err:
        msg = f'cannot read {what} {str(path)!r}: it is not an .npz archive, or it is damaged ({why(err)}); {hint}.'
        raise error(msg) from err
    if bare:
        msg = f'{str(path)!r} holds one bare array (.npy), not a {what}; {hint}.'
        raise error(msg)
    if META_KEY not in arrays:
        msg = f'{str(path)!r} is an .npz archive without vtube metadata, not a {what}; {hint}.'
        raise error(msg)
    try:
        meta = json.loads(str(arrays.pop(META_KEY)))
    except ValueError as err:
        msg = f'cannot read {what} {str(path)!r}: its metadata is damaged ({err}); {hint}.'
        raise error(msg) from err
    if not isinstance(meta, dict):
        msg = f'cannot read {what} {str(path)!r}: its metadata is a JSON {type(meta).__name__}, not an object; {hint}.'
        raise error(msg)
    return arrays, meta


def why(err: BaseException) -> str:
    """Why numpy could not read a file, in one line; pickled objects named as refused (numpy's own message
    suggests turning pickling on for the load, which would let a data file run code: vtube never does)."""
    text = ' '.join(str(err).split())
    return (
        'it holds pickled objects, which are never loaded: a data file must not run code' if 'pickle' in text else text
    )
