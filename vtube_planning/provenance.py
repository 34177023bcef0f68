"""Where a result comes from: recorded in every file vtube writes (plans, logs, reports, submissions).

`provenance` gives the package version, the command line, the time (UTC), and when given the scene (its
name, file and a hash of its content), the plan (a hash of its file) and the seeds. `copy_scene` writes the
scene's file beside the results, so that a folder of results says exactly what was flown. `source_commit` names
the git commit of the code, for results committed beside it.
"""

from __future__ import annotations

import hashlib
import shlex
import subprocess
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from datetime import datetime, timezone
from itertools import pairwise
from pathlib import Path
from typing import TYPE_CHECKING, Any

from vtube_planning import __version__
from vtube_planning.files import write_atomically

if TYPE_CHECKING:
    from vtube_planning.geometry.scene import Scene


def sha256_of(data: bytes | str) -> str:
    """The SHA-256 of bytes, or of text as UTF-8, in hex."""
    return hashlib.sha256(data.encode('utf-8') if isinstance(data, str) else data).hexdigest()


_COMMAND: ContextVar[tuple[str, ...] | None] = ContextVar('vtube_command', default=None)


@contextmanager
def command_line(words: Sequence[str]) -> Iterator[None]:
    """Record ``words`` as the command line of everything written inside (the CLI's own arguments, which are not
    ``sys.argv`` when it is called from Python)."""
    token = _COMMAND.set(tuple(words))
    try:
        yield
    finally:
        _COMMAND.reset(token)


def provenance(
    *, scene: Scene | None = None, plan_file: Path | None = None, seeds: list[int] | None = None
) -> dict[str, Any]:
    """The record of where a result comes from (module docstring); JSON-ready."""
    record: dict[str, Any] = {
        'vtube_version': __version__,
        'command': shlex.join(_COMMAND.get() or sys.argv),
        'utc': datetime.now(timezone.utc).isoformat(timespec='seconds'),
    }
    if scene is not None:
        record |= {'scene': scene.name, 'scene_source': scene.source, 'scene_sha256': sha256_of(scene.text)}
    if plan_file is not None:
        record['plan_sha256'] = sha256_of(Path(plan_file).read_bytes())
    if seeds is not None:
        record['seeds'] = list(seeds)
    return record


def source_commit() -> str | None:
    """The git commit the package's code is at (``-dirty`` added when its code, not its results, differs from it);
    None when the code is not a git checkout of its own (an installed copy)."""
    root = Path(__file__).resolve().parents[1]

    def git(*words: str) -> str | None:
        try:
            done = subprocess.run(
                ['git', '-C', str(root), *words], capture_output=True, text=True, timeout=20, check=False
            )
        except (OSError, subprocess.TimeoutExpired):
            return None
        return done.stdout.strip() if done.returncode == 0 else None

    top = git('rev-parse', '--show-toplevel')
    if top is None or Path(top).resolve() != root:  # not a checkout, or a copy inside another repository
        return None
    code = ('vtube', 'vtube_planning', 'robotarium_exp', 'unicycle_mapping', 'submission', 'pyproject.toml')
    head, changed = git('rev-parse', 'HEAD'), git('status', '--porcelain', '--untracked-files=no', '--', *code)
    return None if head is None else head + ('-dirty' if changed else '')


def made_text(record: dict[str, Any]) -> str:
    """What made a result, in one line: the command, the version, the commit and the time of a
    `provenance` record with ``commit`` (`source_commit`)."""
    commit = (record.get('commit') or 'not a git checkout')[:12]
    return (
        f'made by `{record.get("command", "?")}` (vtube {record.get("vtube_version", "?")}, commit {commit}, '
        f'{record.get("utc", "?")})'
    )


def made_counts(made: list[dict[str, Any]], finished: int) -> list[str]:
    """How many runs each record of a campaign's ``provenance.json`` made: the runs done before the next record
    (or the ``finished`` runs now, after the last) less those done before it. Where a record says nothing of the
    runs done before it (written before they were recorded): the runs each record was to make."""
    before = [entry['done_before'] for entry in made if isinstance(entry.get('done_before'), int)]
    if len(before) < len(made):
        return [str(entry.get('to_run', '?')) for entry in made]
    before.append(finished)
    return [str(max(after - now, 0)) for now, after in pairwise(before)]


def copy_scene(scene: Scene, folder: Path) -> Path:
    """Write the scene's file into ``folder`` as ``scene_<name>.toml`` (the same bytes it was read from)."""
    path = folder / f'scene_{scene.name}.toml'
    return write_atomically(path, scene.text)
