"""How quickly the command line answers: ``vtube --version``, ``vtube --help`` and every command's refusal of bad
input, against ``python -c pass``.

    python -m benchmarks.cli_startup [--repeats 5]

Each case runs as ``python -m vtube ...`` in a child process from the repository root (so the tree's code runs), in
rounds: one run of every case, ``python -c pass`` first, then again, so that a load that comes and goes slows them
alike. Printed per case: the median wall time, the median CPU time of the child (user + system: what the command
itself costs, whatever else shares the cores), both as a ratio to ``python -c pass`` in the same rounds, and the
goal of issue 51 (``--version`` and ``--help`` under 0.3 s, a refusal under 1 s), judged on the CPU time (on an
idle machine wall and CPU time agree; on a busy one the wall time is the CPU time stretched by the load). A refusal
is checked to be one: exit 2 with an ``error:`` line. The refusals are each command's cheapest path to an error
that is not the parser's (an unknown scene, a missing file), after its options parsed, plus one refusal by the
parser; the CLI imports a command's work only when it runs (`vtube.cli.app`).
"""

from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
QUICK_S = 0.3
"""The goal for ``--version`` and ``--help``."""
REFUSAL_S = 1.0
"""The goal for a refusal of bad input."""

CASES: tuple[tuple[str, float | None], ...] = (
    ('python -c pass', None),
    ('vtube --version', QUICK_S),
    ('vtube --help', QUICK_S),
    ('vtube simulate A --out {out} --seed -1', REFUSAL_S),
    ('vtube scene show {missing}.toml', REFUSAL_S),
    ('vtube scene export Z', REFUSAL_S),
    ('vtube tube generate {missing}.toml --out {out}/x.toml', REFUSAL_S),
    ('vtube tube example nowhere {out}/map.toml', REFUSAL_S),
    ('vtube plan Z --out {out}', REFUSAL_S),
    ('vtube simulate Z --out {out}', REFUSAL_S),
    ('vtube study --out {out} --scenes Z', REFUSAL_S),
    ('vtube ablation --out {out} --scenes Z', REFUSAL_S),
    ('vtube campaign example nowhere {out}/c.toml', REFUSAL_S),
    ('vtube campaign run {missing}.toml --out {out}', REFUSAL_S),
    ('vtube campaign report {missing}', REFUSAL_S),
    ('vtube campaign verify {missing}', REFUSAL_S),
    ('vtube robotarium run Z --out {out}', REFUSAL_S),
    ('vtube robotarium compare Z --out {out}', REFUSAL_S),
    ('vtube robotarium sweep robotarium_curve --out {file}', REFUSAL_S),
    ('vtube submission build Z --out {out}/x.py', REFUSAL_S),
    ('vtube submission check {missing}.py', REFUSAL_S),
    ('vtube analyze {missing} --out {out}', REFUSAL_S),
    ('vtube export {missing}.npz --format csv --out {out}/x.csv', REFUSAL_S),
    ('vtube replay {missing}.npz --out {out}/x.html', REFUSAL_S),
    ('vtube demo --out {file}', REFUSAL_S),
)
"""Each case's command line (``{out}`` an empty folder, ``{missing}`` a path that does not exist, ``{file}`` a file
where a folder belongs) and its goal in seconds (None: the reference)."""


def command(case: str, folder: Path) -> list[str]:
    """The child's argv for ``case``."""
    words = case.format(out=folder / 'out', missing=folder / 'missing', file=folder / 'a_file').split()
    return [sys.executable, *(['-m', 'vtube'] if words[0] == 'vtube' else []), *words[1:]]


def run_once(argv: list[str]) -> tuple[float, float, int, str]:
    """Wall and CPU seconds of one child run (its CPU time: what the children's total grew by once it was
    reaped), its exit code and what it wrote on stderr."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(argv, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, check=False)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, done.returncode, done.stderr


def measure(repeats: int) -> dict[str, tuple[list[float], list[float], int, str]]:
    """Per case: wall and CPU seconds of every round, the last exit code and stderr."""
    found: dict[str, tuple[list[float], list[float], int, str]] = {case: ([], [], 0, '') for case, _ in CASES}
    with tempfile.TemporaryDirectory(prefix='vtube-startup-') as name:
        folder = Path(name)
        (folder / 'out').mkdir()
        (folder / 'a_file').write_text('not a folder\n', encoding='utf-8')
        for _ in range(max(1, repeats)):
            for case, _ in CASES:
                wall, cpu, code, stderr = run_once(command(case, folder))
                walls, cpus, _, _ = found[case]
                found[case] = ([*walls, wall], [*cpus, cpu], code, stderr)
    return found


def table(found: dict[str, tuple[list[float], list[float], int, str]]) -> tuple[list[str], int]:
    """The printed rows and how many cases missed their goal or were not what they claim."""
    base_wall = statistics.median(found['python -c pass'][0])
    base_cpu = statistics.median(found['python -c pass'][1])
    rows = [f'{"case":<58} {"wall [s]":>8} {"x pass":>7} {"CPU [s]":>8} {"x pass":>7}  goal (CPU)']
    missed = 0
    for case, goal in CASES:
        walls, cpus, code, stderr = found[case]
        wall, cpu = statistics.median(walls), statistics.median(cpus)
        verdict = ''
        if goal is not None:
            refused = goal == REFUSAL_S
            right = (code == 2 and 'error:' in stderr) if refused else code == 0
            held = right and cpu < goal
            missed += not held
            what = '' if right else f' (exit {code}: {"not a refusal" if refused else "failed"})'
            verdict = f'< {goal:.1f} s {"held" if held else "MISSED"}{what}'
        rows.append(
            f'{case:<58} {wall:>8.3f} {wall / base_wall:>7.1f} {cpu:>8.3f} {cpu / max(base_cpu, 1e-3):>7.1f}  {verdict}'
        )
    return rows, missed


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--repeats', type=int, default=5, help='rounds of every case (the medians are printed)')
    args = parser.parse_args()
    rows, missed = table(measure(args.repeats))
    print('\n'.join(rows))
    print(f'\n{len(CASES) - 1 - missed} of {len(CASES) - 1} cases within their goal (medians of {args.repeats}).')
    return 1 if missed else 0


if __name__ == '__main__':
    sys.exit(main())
