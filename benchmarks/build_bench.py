"""Where `vtube submission build` spends its time, before and after the runs went to every core and the
initializer's durations and the runs' initialized states were reused, side by side in one run; the first build of a
shipped scene, whose formation's durations ship with the package; and the rebuild after a change of control
parameters.

    python -m benchmarks.build_bench [--scene robotarium_curve] [--seeds 3] [--initializer-seeds 200]

Each case is what `vtube submission build SCENE` does (the plan, the file, its preflight: ``--seeds`` seeds under each
testbed model of the check, the PyPI simulator's run when it is installed, V2's initializer alone over the initializer
seeds) in this process, with a cache folder of its own (`submission.reuse`, through ``VTUBE_CACHE_DIR``):

- **before**: the runs one after another (``workers=1``), nothing reused (``reuse=False``): the build as it was;
- **after**: the runs ``os.cpu_count()`` at a time, the cache empty and the shipped durations
  (`submission.reuse.SHIPPED`) set aside: the first build of an own formation (a seed's runs under the testbed
  models after the first take its initialized state from that one);
- **shipped**: as after, in a cache of its own, with the shipped durations: the first build of a shipped scene on a
  fresh machine (the initializer's 200 seeds are the table's, made by `submission.shipped`);
- **rebuild**: shipped, then the same scene with one control gain changed (``[control] keeping_gain`` x 1.1): the
  plan is made and the file run again, the initializer's durations and the runs' initialized states are the first
  build's (same formation).

Per case: the wall time of each stage (plan and file, the runs, the initializer) and in all, the CPU time of this
process and its children, and the load average (1 min) at its end. The files of before, after and shipped must
be the same but for their build stamp (the benchmark exits 1 otherwise).
"""

from __future__ import annotations

import argparse
import itertools
import os
import resource
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager, nullcontext
from pathlib import Path

from robotarium_exp.scene import load_scene
from submission import reuse
from submission.builder import BUILD_STAMP, build_declared
from submission.reuse import CACHE_ENV
from vtube.pipeline import plan_for

STAGES = ('plan and file', 'runs', 'initializer')
CONTROL_CHANGE = '\n[control]\nkeeping_gain = 5.5e-4  # x 1.1: a change of control parameters only\n'


def cpu_s() -> float:
    """CPU seconds of this process and of its children waited for."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


@contextmanager
def cache(folder: Path) -> Iterator[None]:
    """``VTUBE_CACHE_DIR`` set to ``folder`` while the block runs."""
    saved = os.environ.get(CACHE_ENV)
    os.environ[CACHE_ENV] = str(folder)
    try:
        yield
    finally:
        if saved is None:
            del os.environ[CACHE_ENV]
        else:
            os.environ[CACHE_ENV] = saved


@contextmanager
def shipped_aside(folder: Path) -> Iterator[None]:
    """The shipped durations out of reach (a path in ``folder`` that does not exist) while the block runs."""
    saved = reuse.SHIPPED
    reuse.SHIPPED = folder / 'no_shipped_durations.json'
    try:
        yield
    finally:
        reuse.SHIPPED = saved


def one_build(
    scene_ref: str | Path, out: Path, workers: int | None, seeds: tuple[int, int], *, reuse: bool = True
) -> tuple[dict[str, float], str]:
    """Wall seconds per stage, in all, CPU and load of one build; and the file's source."""
    marks: list[tuple[str, float]] = []
    start, cpu = time.perf_counter(), cpu_s()

    def progress(text: str) -> None:
        stage = 'initializer' if text.startswith("V2's initializer") else 'runs'
        if not marks or marks[-1][0] != stage:
            marks.append((stage, time.perf_counter()))

    scene = load_scene(scene_ref)
    submission, report, _ = build_declared(
        scene,
        plan_for(scene),
        out,
        seeds=seeds[0],
        initializer_seeds=seeds[1],
        progress=progress,
        workers=workers,
        reuse=reuse,
    )
    end = time.perf_counter()
    if not report.passed:
        print(f'the build of {scene_ref} failed its check: {report.problems}', file=sys.stderr)
    bounds = [start, *(at for _, at in marks), end]
    times = dict(zip(STAGES, (b - a for a, b in itertools.pairwise(bounds))))
    return {**times, 'wall': end - start, 'cpu': cpu_s() - cpu, 'load': os.getloadavg()[0]}, submission.source


def unstamped(source: str) -> list[str]:
    return [line for line in source.splitlines() if not line.startswith(BUILD_STAMP)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--scene', default='robotarium_curve')
    parser.add_argument('--seeds', type=int, default=3)
    parser.add_argument('--initializer-seeds', type=int, default=200)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix='vtube-build-bench-') as folder:
        root, seeds = Path(folder), (args.seeds, args.initializer_seeds)
        changed = root / f'{args.scene}_gain.toml'
        changed.write_text(load_scene(args.scene).text + CONTROL_CHANGE, encoding='utf-8')
        cases: list[tuple[str, Callable[[], tuple[dict[str, float], str]]]] = [
            ('before', lambda: one_build(args.scene, root / 'before.py', 1, seeds, reuse=False)),
            ('after', lambda: one_build(args.scene, root / 'after.py', None, seeds)),
            ('shipped', lambda: one_build(args.scene, root / 'shipped.py', None, seeds)),
            ('rebuild', lambda: one_build(changed, root / 'rebuild.py', None, seeds)),
        ]
        rows, sources = {}, {}
        for name, run in cases:
            aside = shipped_aside(root) if name == 'after' else nullcontext()
            with cache(root / f'cache-{"shipped" if name == "rebuild" else name}'), aside:
                rows[name], sources[name] = run()
    print(
        f'{args.scene}: {args.seeds} seeds per model, {args.initializer_seeds} initializer seeds, {os.cpu_count()} cores'
    )
    print(f'{"":<16}' + ''.join(f'{name:>10}' for name in rows))
    for key in (*STAGES, 'wall', 'cpu', 'load'):
        unit = '' if key == 'load' else ' [s]'
        print(f'{key + unit:<16}' + ''.join(f'{row.get(key, 0.0):>10.1f}' for row in rows.values()))
    same = unstamped(sources['before']) == unstamped(sources['after']) == unstamped(sources['shipped'])
    print(f'before, after and shipped build the same file (but the build stamp): {"yes" if same else "NO"}')
    if not same:
        raise SystemExit(1)


if __name__ == '__main__':
    main()
