"""map_unordered on local processes (spawned): every item once, each result with its index, errors propagate."""

from __future__ import annotations

import math
import operator
import os

import pytest

from vtube_planning.studies.executors import map_unordered


def test_local_processes_return_every_result_with_its_index() -> None:
    items = [0.0, 1.0, 4.0, 9.0, 16.0]
    results = dict(map_unordered(math.sqrt, items, workers=2))
    assert results == {0: 0.0, 1: 1.0, 2: 2.0, 3: 3.0, 4: 4.0}


def test_local_workers_compute_on_one_thread_each() -> None:
    # the workers share the cores already: a large swarm's foresight must not start numba's threads in each
    here = os.getenv('NUMBA_NUM_THREADS')
    assert dict(map_unordered(os.getenv, ['NUMBA_NUM_THREADS'] * 2, workers=2)) == {0: '1', 1: '1'}
    assert os.getenv('NUMBA_NUM_THREADS') == here  # set in the workers, not here


def test_an_error_in_a_local_process_propagates() -> None:
    with pytest.raises(TypeError):
        list(map_unordered(operator.neg, [1, 'x', 3], workers=2))


SLEEPER = """
import sys, time
from vtube_planning.studies.executors import map_unordered
if __name__ == '__main__':
    for _ in map_unordered(time.sleep, [60.0, 60.0], workers=2):
        pass
"""

INITIALIZER = """
import numpy as np
from robotarium_exp.initializer import initializer_durations
if __name__ == '__main__':  # twenty robots: each seed's initialization takes far longer than the test waits
    ic = np.array([[-1.2 + 0.4 * (k % 6), -0.6 + 0.4 * (k // 6), 0.0] for k in range(20)]).T
    initializer_durations(ic, range(8), workers=2)
"""


def _stat(pid: int | str) -> list[str] | None:
    """The fields of /proc/PID/stat after the command's name (state first, then the parent's pid), or None."""
    from pathlib import Path

    try:
        return Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    except (OSError, IndexError):
        return None


@pytest.mark.parametrize('program', [SLEEPER, INITIALIZER], ids=['campaign', 'submission build initializer'])
def test_workers_end_when_their_parent_is_killed(tmp_path, program: str) -> None:
    """Issue 49: `kill -9` of `campaign run` left its workers running (still alive 20 s later); issue 50: so did
    `submission build`'s initializer seeds. Each worker ends itself once its parent is gone."""
    import os
    import signal
    import subprocess
    import sys
    import time

    script = tmp_path / 'sleeper.py'
    script.write_text(program, encoding='utf-8')
    parent = subprocess.Popen([sys.executable, str(script)])

    def children() -> list[int]:
        return [int(e) for e in os.listdir('/proc') if e.isdigit() and (_stat(e) or ['', '0'])[1] == str(parent.pid)]

    deadline = time.monotonic() + 60.0
    while len(children()) < 2 and time.monotonic() < deadline:  # the two workers (and spawn's helpers)
        time.sleep(0.2)
    workers = children()
    assert len(workers) >= 2
    os.kill(parent.pid, signal.SIGKILL)
    parent.wait()
    time.sleep(3.0)  # a few times WATCH_PARENT_S
    alive = [pid for pid in workers if (_stat(pid) or ['Z'])[0] != 'Z']  # gone, or a zombie: ended
    assert alive == []
