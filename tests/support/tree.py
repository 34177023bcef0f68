"""What a test run leaves in the working tree: the untracked paths, ignored or not, that were not there before.

`tests/conftest.py` lists them when the session starts and again when it ends, and fails the run naming every
new one (tests write to temporary folders only). Caches that Python and the tools make beside the sources
(``__pycache__``, ``.pytest_cache``, ``.mypy_cache``, ``.ruff_cache``) are not counted. Outside a git checkout
there is nothing to compare: `untracked_paths` gives None.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

CACHES = ('__pycache__', '.pytest_cache', '.mypy_cache', '.ruff_cache')


def untracked_paths(root: Path) -> frozenset[str] | None:
    """Every untracked path under ``root`` (an ignored folder as one entry, ``out/``), caches left out; None when
    ``root`` is not the top of a git checkout or git is missing."""
    try:
        top = subprocess.run(
            ['git', 'rev-parse', '--show-toplevel'], cwd=root, capture_output=True, text=True, check=False
        )
    except OSError:
        return None
    if top.returncode != 0 or Path(top.stdout.strip()).resolve() != root.resolve():
        return None
    listed = subprocess.run(
        ['git', 'status', '--porcelain=v1', '-z', '--untracked-files=all', '--ignored=matching'],
        cwd=root,
        capture_output=True,
        text=True,
        check=True,
    )
    paths = (entry[3:] for entry in listed.stdout.split('\0') if entry[:3] in ('?? ', '!! '))
    return frozenset(path for path in paths if not set(Path(path).parts) & set(CACHES))


def left_behind(before: frozenset[str] | None, after: frozenset[str] | None) -> list[str]:
    """The paths in ``after`` that were not in ``before`` (nothing when either is None)."""
    if before is None or after is None:
        return []
    return sorted(after - before)
