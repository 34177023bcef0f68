"""How long CI takes: ``.ci/run`` on a clean clone, stage by stage, in wall and CPU seconds.

    python -m benchmarks.ci_time [--ref HEAD]

The repository's commit ``--ref`` is cloned into a temporary folder (a clean clone: the commit's files only, no
``.venv``, no caches but pip's own download cache) and its ``.ci/run`` runs there as CI runs it, traced by bash
(``set -x``, the trace on a file of its own): each command of the script is stamped when it starts with the wall
clock and the CPU seconds of the script's finished children so far (``/proc/PID/stat``: user and system time of
the children it has waited for, the commands' subprocesses and test workers included). A stage's time is the
difference to the next stamp; the total is measured around the whole run. Printed: each stage's command, wall and
CPU seconds, the total, ``.ci/run``'s exit code, the machine's cores and its load average before and after. On a
machine shared with other work the wall time is stretched by the load; the CPU time is what CI itself costs, and
CPU / cores is the least wall time it can take on an idle machine of that many cores. The goal of issue 51 is
6 minutes of wall time on 2 cores. A failed ``.ci/run`` (or clone) exits 1, its output's tail printed.
"""

from __future__ import annotations

import argparse
import os
import resource
import shlex
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MARK = '+ci_time'
"""Starts every trace line (bash repeats its first character once per level: ``++ci_time`` one level down)."""
PS4 = MARK + r' $EPOCHREALTIME $(read -ra s < /proc/$$/stat; echo $((s[15] + s[16]))) '
"""The trace prompt: the mark, the wall clock, the script shell's finished children's CPU in clock ticks."""
GOAL_S = 360.0
"""Issue 51's goal for ``.ci/run`` on 2 cores."""


@dataclass(frozen=True)
class Stage:
    """One traced command of ``.ci/run``: what ran, when it started (wall clock) and the CPU seconds of the script's
    finished children at that moment."""

    command: str
    start_s: float
    cpu_s: float


def stages(trace: str, ticks_per_s: float) -> list[Stage]:
    """The traced commands of the script itself, in order: one level below the outermost line (the ``. ./.ci/run``
    that runs it), not those of its command substitutions (deeper) nor a multi-line command's further lines."""
    marked = []
    for line in trace.splitlines():
        depth = len(line) - len(line.lstrip('+'))
        if depth and line[depth:].startswith(MARK[1:] + ' '):
            _, wall, ticks, command = line[depth:].split(' ', 3)
            marked.append((depth, Stage(command, float(wall), int(ticks) / ticks_per_s)))
    outer = min((depth for depth, _ in marked), default=0)
    return [stage for depth, stage in marked if depth == outer + 1]


def rows(found: list[Stage], end_s: float, end_cpu_s: float, width: int = 72) -> list[str]:
    """Each stage's wall and CPU seconds until the next stage starts (the last one until ``end_s``,
    ``end_cpu_s``), commands longer than ``width`` cut with an ellipsis."""
    lines = [f'{"stage (a command of .ci/run)":<{width}} {"wall [s]":>9} {"CPU [s]":>9}']
    ends = [(stage.start_s, stage.cpu_s) for stage in found[1:]] + [(end_s, end_cpu_s)]
    for stage, (until_s, until_cpu_s) in zip(found, ends, strict=True):
        text = stage.command if len(stage.command) <= width else stage.command[: width - 3] + '...'
        lines.append(f'{text:<{width}} {until_s - stage.start_s:>9.1f} {until_cpu_s - stage.cpu_s:>9.1f}')
    return lines


def children_cpu_s() -> float:
    """User and system seconds of this process's finished children."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_ci(clone: Path, trace: Path) -> subprocess.CompletedProcess[str]:
    """``.ci/run`` in ``clone``, traced to ``trace`` (``$0`` is the script's path, as when it runs itself)."""
    script = f'exec 9>{shlex.quote(str(trace))}; BASH_XTRACEFD=9; PS4={shlex.quote(PS4)}; set -x; . ./.ci/run'
    return subprocess.run(['bash', '-c', script, '.ci/run'], cwd=clone, capture_output=True, text=True, check=False)


def git(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    """A git command's outcome (never raises on its exit code)."""
    return subprocess.run(['git', *args], cwd=cwd, capture_output=True, text=True, check=False)


def clean_clone(ref: str, clone: Path) -> str:
    """Clone the repository into ``clone`` at ``ref``; its commit. An unknown ref is bad input (exit 2)."""
    if git('rev-parse', '--verify', '--quiet', f'{ref}^{{commit}}', cwd=ROOT).returncode != 0:
        print(f'error: {ref!r} is no commit of {ROOT}; give a branch, tag or commit (default HEAD).', file=sys.stderr)
        raise SystemExit(2)
    cloned = git('clone', '--quiet', '--no-hardlinks', str(ROOT), str(clone))
    if cloned.returncode == 0:
        cloned = git('checkout', '--quiet', ref, cwd=clone)
    if cloned.returncode != 0:
        print(f'could not clone {ROOT} at {ref}: {cloned.stderr.strip()}')
        raise SystemExit(1)
    return git('rev-parse', 'HEAD', cwd=clone).stdout.strip()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--ref', default='HEAD', help='the commit to clone and run (default HEAD)')
    args = parser.parse_args()
    ticks_per_s = float(os.sysconf('SC_CLK_TCK'))
    with tempfile.TemporaryDirectory(prefix='vtube-ci-time-') as name:
        clone, trace = Path(name) / 'clone', Path(name) / 'trace.txt'
        commit = clean_clone(args.ref, clone)
        load_before = os.getloadavg()[0]
        start_s, start_cpu_s = time.time(), children_cpu_s()
        done = run_ci(clone, trace)
        end_s, cpu_s = time.time(), children_cpu_s() - start_cpu_s
        found = stages(trace.read_text(encoding='utf-8'), ticks_per_s)
    print(f'.ci/run on a clean clone of commit {commit}: exit {done.returncode}')
    print(f'{os.cpu_count()} cores, load average {load_before:.1f} before, {os.getloadavg()[0]:.1f} after\n')
    if found:  # the script's shell started with no finished children: its stamps and this total share one origin
        print('\n'.join(rows(found, end_s, cpu_s)))
    total_s, cores = end_s - start_s, os.cpu_count() or 1
    print(f'\ntotal {total_s:.1f} s wall ({total_s / 60:.1f} min), {cpu_s:.1f} s CPU')
    print(f'least wall time on an idle machine of {cores} cores (CPU / cores): {cpu_s / cores:.1f} s')
    print(f'goal (issue 51): {GOAL_S / 60:.0f} min of wall time on 2 cores')
    if done.returncode != 0:
        print(f'\n.ci/run failed; the tail of its output:\n{(done.stdout + done.stderr)[-3000:]}')
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
