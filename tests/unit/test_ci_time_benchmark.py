"""``benchmarks/ci_time.py``: the stages read from a made-up bash trace and the table printed of them (nothing runs;
``tests/integration/test_ci_time_benchmark.py`` traces a real script)."""

from __future__ import annotations

import pytest

from benchmarks.ci_time import MARK, PS4, Stage, rows, stages

TRACE = f"""{MARK} 100.00 0 . ./.ci/run
+{MARK} 100.25 0 set -uo pipefail
++{MARK} 100.50 2 dirname .ci/run
+{MARK} 100.75 4 cd .ci/..
+{MARK} 101.00 4 python3 -c '
print(1)'
+{MARK} 131.00 1504 .venv/bin/ruff check .
some output of the script that was not traced
+{MARK} 136.50 2004 exit 0
"""


def test_the_stages_are_the_scripts_own_commands_with_their_stamps() -> None:
    found = stages(TRACE, ticks_per_s=100.0)
    assert [stage.command for stage in found] == [
        'set -uo pipefail',
        'cd .ci/..',
        "python3 -c '",
        '.venv/bin/ruff check .',
        'exit 0',
    ]
    assert found[2] == Stage("python3 -c '", 101.0, 0.04) and found[3].cpu_s == pytest.approx(15.04)
    assert stages('', 100.0) == [] and stages('+ plain trace\n', 100.0) == []


def test_each_stage_lasts_until_the_next_one_starts_and_the_last_until_the_end() -> None:
    found = stages(TRACE, ticks_per_s=100.0)
    table = rows(found, end_s=137.0, end_cpu_s=20.5, width=24)
    assert table[0].split() == ['stage', '(a', 'command', 'of', '.ci/run)', 'wall', '[s]', 'CPU', '[s]']
    python = next(row for row in table if row.startswith('python3'))
    assert python.split()[-2:] == ['30.0', '15.0']  # 101.00 -> 131.00 s, 0.04 -> 15.04 s of CPU
    assert table[-1].split() == ['exit', '0', '0.5', '0.5']  # until the end: 137.0 s, 20.5 s of CPU
    assert (
        table[4].startswith('.venv/bin/ruff check .')
        and len(rows([Stage('x' * 30, 0.0, 0.0)], 1.0, 0.0, 24)[1].split()[0]) == 24
    )
    assert PS4.startswith(MARK + ' ') and '/proc/$$/stat' in PS4
