"""``benchmarks/cli_startup.py``: its cases' command lines and its verdicts, on made-up timings (nothing is run)."""

from __future__ import annotations

import sys
from pathlib import Path

from benchmarks.cli_startup import CASES, QUICK_S, REFUSAL_S, command, table


def timings(cpu_s: float, code: int, stderr: str) -> tuple[list[float], list[float], int, str]:
    return [2 * cpu_s], [cpu_s], code, stderr


def test_each_case_runs_the_trees_vtube_or_python() -> None:
    assert CASES[0] == ('python -c pass', None) and dict(CASES)['vtube --version'] == QUICK_S
    folder = Path('/x')
    assert command('python -c pass', folder) == [sys.executable, '-c', 'pass']
    assert command('vtube plan Z --out {out}', folder) == [
        sys.executable,
        '-m',
        'vtube',
        'plan',
        'Z',
        '--out',
        '/x/out',
    ]
    assert all(goal in (QUICK_S, REFUSAL_S) for _, goal in CASES[1:])


def test_the_verdicts_judge_the_cpu_time_and_what_the_command_did() -> None:
    found = {case: timings(0.01, 0, '') for case, _ in CASES}
    for case, goal in CASES[1:]:
        found[case] = timings(0.1, 0, '') if goal == QUICK_S else timings(0.5, 2, 'error: no such scene')
    rows, missed = table(found)
    assert missed == 0 and len(rows) == len(CASES) + 1
    version = next(row for row in rows if row.startswith('vtube --version'))
    assert version.split()[2:7] == ['0.200', '10.0', '0.100', '10.0', '<']  # wall, ratio, CPU, ratio vs python
    slow, quiet = CASES[3][0], CASES[4][0]
    found[slow] = timings(1.5, 2, 'error: x')  # over the goal
    found[quiet] = timings(0.5, 0, '')  # exit 0: not a refusal
    rows, missed = table(found)
    assert missed == 2
    assert rows[4].endswith('MISSED') and rows[5].endswith('MISSED (exit 0: not a refusal)')
