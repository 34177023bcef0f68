"""The suite's two rooms, told by path: ``tests/unit`` (fast, in-process, the inner loop: ``pytest tests/unit``) and
``tests/integration`` (end-to-end runs, subprocesses, terminals, real recordings). Each test gets the marker of its
room, so ``pytest -m unit`` and ``pytest -m integration`` select them from anywhere; a test file outside both rooms
is a usage error.

With pytest-xdist, ``pytest -n 2 --dist loadfile`` keeps each file on one worker, so that module fixtures (the demo
run among them) are built once. Every test process uses one BLAS thread (unless OPENBLAS_NUM_THREADS is set): OpenBLAS threads spin while they
wait, so two workers with two threads each on two cores run the small QPs of the certificates many times slower.
The thread count changes no bit of any result (tests/integration/test_regression.py).

Tests write to temporary folders only: the session lists the untracked paths of the working tree when it starts and
when it ends (`tests.support.tree`), and a run that leaves a new one fails, naming it (outside a git checkout there
is nothing to compare and nothing is checked). The cache of `submission.reuse` is a temporary folder of the session
(``VTUBE_CACHE_DIR``, inherited by the subprocesses), never the user's.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.support.tree import left_behind, untracked_paths

os.environ.setdefault('OPENBLAS_NUM_THREADS', '1')  # before numpy is imported, inherited by workers and subprocesses

ROOMS = ('unit', 'integration')
HERE = Path(__file__).resolve().parent
TREE = pytest.StashKey['frozenset[str] | None']()


def room_of(path: Path) -> str:
    """The room a test file lives in, or an error naming the file and where it belongs."""
    relative = path.resolve().relative_to(HERE)
    if relative.parts[0] not in ROOMS:
        raise pytest.UsageError(
            f'{path}: every test lives under tests/unit/ (fast, in-process) or tests/integration/ (end-to-end); '
            'move it into one of them'
        )
    return relative.parts[0]


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        item.add_marker(getattr(pytest.mark, room_of(item.path)))


def _controller(config: pytest.Config) -> bool:
    """Not a pytest-xdist worker (the controller sees the whole run)."""
    return not hasattr(config, 'workerinput')


@pytest.fixture(autouse=True, scope='session')
def _session_cache(tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    """`submission.reuse`'s cache in a temporary folder while the session runs."""
    saved = os.environ.get('VTUBE_CACHE_DIR')
    os.environ['VTUBE_CACHE_DIR'] = str(tmp_path_factory.mktemp('vtube-cache'))
    yield
    if saved is None:
        del os.environ['VTUBE_CACHE_DIR']
    else:
        os.environ['VTUBE_CACHE_DIR'] = saved


def pytest_sessionstart(session: pytest.Session) -> None:
    if _controller(session.config):
        session.config.stash[TREE] = untracked_paths(HERE.parent)


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    if not _controller(session.config) or TREE not in session.config.stash:
        return
    left = left_behind(session.config.stash[TREE], untracked_paths(HERE.parent))
    if left:
        reporter = session.config.pluginmanager.get_plugin('terminalreporter')
        message = (
            f'the test run left {len(left)} new path(s) in the working tree (tests write to temporary folders '
            f'only, e.g. tmp_path): ' + ', '.join(left)
        )
        if reporter is not None:
            reporter.write_line(f'ERROR: {message}', red=True, bold=True)
        session.exitstatus = pytest.ExitCode.TESTS_FAILED
