"""``benchmarks/ci_time.py`` traces a real ``.ci/run`` (a small one, in a temporary folder): every command stamped,
the CPU of a busy one counted, the script's own output kept apart from the trace."""

from __future__ import annotations

import os

from benchmarks.ci_time import rows, run_ci, stages

SCRIPT = """#!/usr/bin/env bash
set -uo pipefail
cd "$(dirname "$0")/.."
echo the script speaks && python3 -c 'import time; t = time.process_time()
while time.process_time() - t < 0.3: pass' && sleep 0.2
exit 3
"""


def test_a_scripts_commands_are_timed_in_wall_and_cpu_seconds(tmp_path) -> None:
    (tmp_path / '.ci').mkdir()
    (tmp_path / '.ci' / 'run').write_text(SCRIPT, encoding='utf-8')
    done = run_ci(tmp_path, tmp_path / 'trace.txt')
    assert done.returncode == 3 and done.stdout == 'the script speaks\n' and 'ci_time' not in done.stderr
    found = stages((tmp_path / 'trace.txt').read_text(encoding='utf-8'), os.sysconf('SC_CLK_TCK'))
    assert [stage.command.split()[0] for stage in found] == ['set', 'cd', 'echo', 'python3', 'sleep', 'exit']
    python, sleep = found[3], found[4]
    assert sleep.cpu_s - python.cpu_s >= 0.25  # the busy child's CPU, counted once it finished
    assert sleep.start_s - python.start_s >= 0.3 and found[5].start_s - sleep.start_s >= 0.2
    assert len(rows(found, found[-1].start_s, found[-1].cpu_s)) == len(found) + 1
