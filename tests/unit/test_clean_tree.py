"""The check that a test run leaves nothing in the working tree (`tests.support.tree`, wired in tests/conftest.py)."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from tests.support.tree import left_behind, untracked_paths

ROOT = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.skipif(shutil.which('git') is None, reason='git is not installed')


def checkout(folder: Path) -> Path:
    """A git checkout in ``folder`` with one committed file and an ignored folder."""
    subprocess.run(['git', 'init', '-q', str(folder)], check=True)
    (folder / 'kept.py').write_text('x = 1\n', encoding='utf-8')
    (folder / '.gitignore').write_text('out/\n', encoding='utf-8')
    subprocess.run(['git', '-C', str(folder), 'add', '.'], check=True)
    return folder


def test_new_files_are_found_ignored_or_not_and_caches_are_not(tmp_path) -> None:
    root = checkout(tmp_path / 'repo')
    before = untracked_paths(root)
    assert before == frozenset()
    (root / 'vtube_t_s.npy').write_bytes(b'')
    (root / 'out').mkdir()
    (root / 'out' / 'plan.npz').write_bytes(b'')
    (root / '__pycache__').mkdir()
    (root / '__pycache__' / 'kept.cpython-312.pyc').write_bytes(b'')
    (root / 'kept.py').write_text('x = 2\n', encoding='utf-8')  # an edit of a tracked file is not a leftover
    assert left_behind(before, untracked_paths(root)) == ['out/', 'vtube_t_s.npy']


def test_nothing_is_compared_outside_a_checkout(tmp_path) -> None:
    (tmp_path / 'loose').mkdir()
    assert untracked_paths(tmp_path / 'loose') is None
    assert untracked_paths(ROOT / 'tests') is None  # inside a checkout, but not its top
    assert left_behind(None, frozenset({'a'})) == []
    assert left_behind(frozenset({'a'}), None) == []
