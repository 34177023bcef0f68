"""Writing a result file: complete or not at all, and never through a link planted at its name.

`write_atomically` writes into a temporary file created exclusively (``O_EXCL``, a random name, mode 0600
until renamed) in the destination's folder, then renames it over the destination (``os.replace``): a reader sees
the old file or the new one, never a part; a kill, a full disk or an error while writing leaves the old file as it
was and removes the temporary one; and a symbolic link at the destination is replaced by the file, not followed
(rename acts on the name, so the file a link points to is never written).
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

Content = bytes | str | Callable[[BinaryIO], None]
"""What to write: bytes, text (UTF-8), or a function that writes into the open binary file it is given."""


def write_atomically(path: str | Path, content: Content) -> Path:
    """Write ``content`` to ``path`` (module doc), creating its folder; returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    descriptor, temporary = tempfile.mkstemp(dir=path.parent, prefix=f'.{path.name}.', suffix='.partial')
    try:
        with os.fdopen(descriptor, 'wb') as handle:
            if callable(content):
                content(handle)
            else:
                handle.write(content.encode('utf-8') if isinstance(content, str) else content)
        os.chmod(temporary, 0o666 & ~_UMASK)
        os.replace(temporary, path)
    except OSError as err:  # a full disk, a file too large, ...: named, with the file left as it was
        Path(temporary).unlink(missing_ok=True)
        if err.filename is not None:
            raise
        msg = f'{err.strerror or err} while writing {path}; the file there was left as it was (free space, or another folder).'
        raise type(err)(err.errno, msg) from err
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return path


def _umask() -> int:
    """The process's umask (read by setting it and back, once, on import: there is no other portable way)."""
    mask = os.umask(0)
    os.umask(mask)
    return mask


_UMASK = _umask()
