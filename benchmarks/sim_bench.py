"""Time of one control step of the swarm controller against N: the step as it runs, beside the step before issue 20
(commit 130bc3a's ``step.py`` and ``tube.py``, read from git at run time), its reference configuration (k-d tree
always, cold projection: the step before the crossover and the warm start) and a dense all-pairs evaluation of the
same avoidance law.

A control step is one call of the swarm step (`vtube_planning.onboard.stepper.SwarmStep`) as the simulator
makes it: project every robot onto the tube, evaluate the command (forward term, avoidance, tube keeping,
saturation), measure the density and advance r_a by (a3) against a constant planned density. Robots sit on a
jittered grid at about one robot per m^2 in a straight tube sized to hold them, so each has a few neighbours, as in
a flying swarm; between calls they move back and forth by one period at 3 m/s along the tube, so the warm
projection starts from the other position's arc lengths. The dense reference computes the avoidance term from all
N^2 distances (in row blocks, to bound memory). All in one process, the three steps called in turn (a load that
comes and goes slows them alike); prints median milliseconds per step, the ratios 130bc3a / step and reference /
step with the largest difference of the old step's commands from the step's, the growth exponent of the step time, the crossover of the neighbour search (all pairs
against the k-d tree, the measurement behind ``KDTREE_ABOVE``), and a row of 100,000 robots with the peak memory
of a process that builds them and runs a few steps.

    python -m benchmarks.sim_bench [--sizes 20 200 1000 2000 10000] [--repeats 5] [--big 100000]
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import time
from dataclasses import asdict, fields, replace
from functools import partial
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from benchmarks._timing import timed, timed_together
from vtube_planning import ArcPath, ArcPiece, SwarmParams, VirtualTube, WidthPart, WidthProfile
from vtube_planning.onboard import (
    KDTREE_ABOVE,
    PlanProfile,
    StepParams,
    SwarmStep,
    avoidance_velocity,
)
from vtube_planning.onboard.scalar import barrier_gain
from vtube_planning.params import ControlParams

DENSE_UP_TO = 10_000
"""The dense avoidance reference is timed up to this many robots (10,000 take about 15 s)."""
BEFORE_ISSUE = '130bc3a'
"""The commit before issue 20's step work: its step (and the tube projection it called) is the baseline column."""


BEFORE_FILES = {
    'projection': 'vtube_planning/geometry/projection.py',
    'tube': 'vtube_planning/geometry/tube.py',
    'step': 'vtube_planning/swarm/step.py',
}
"""What the step work changed, in the order the old versions are loaded (each may import the ones before it)."""


def load_before(commit: str) -> tuple[ModuleType, ModuleType] | str:
    """The modules ``tube`` and ``step`` as of ``commit`` (with the ``projection`` they import), read with ``git
    show`` and run as module objects of their own (the rest of the package is today's); or why not."""
    root = Path(__file__).resolve().parents[1]
    modules = {}
    for name, path in BEFORE_FILES.items():
        try:
            shown = subprocess.run(
                ['git', 'show', f'{commit}:{path}'], cwd=root, capture_output=True, text=True, check=False
            )
        except OSError as error:
            return f'git is unavailable ({error})'
        if shown.returncode != 0:
            return f'git show {commit}:{path} failed: {shown.stderr.strip()}'
        source = shown.stdout
        for loaded, module in modules.items():  # the old modules import each other, not today's
            source = source.replace(
                f'from {BEFORE_FILES[loaded][:-3].replace("/", ".")} import', f'from {module.__name__} import'
            )
        module = ModuleType(f'_sim_bench_{commit}_{name}')
        sys.modules[module.__name__] = module  # dataclasses look their module up
        exec(compile(source, f'{commit}:{path}', 'exec'), module.__dict__)  # noqa: S102 - the repository's own code
        modules[name] = module
    return modules['tube'], modules['step']


def stepper_before(
    before: tuple[ModuleType, ModuleType], tube: VirtualTube, params: StepParams, r_a: np.ndarray
) -> Any:
    """``stepper`` built from the old modules: the old tube on the same centre line and widths, the old step with
    the same numbers except the neighbour search's crossover, which keeps the old default. Parameters added since
    (the delay compensation) are left out, and refused unless they are at their defaults, which switch them off."""
    old_tube, old_step = before
    tube = old_tube.VirtualTube(tube.center, tube.width, tube.name)
    known = {field.name for field in fields(old_step.StepParams)}
    newer = {key: value for key, value in asdict(params).items() if key not in known and key != 'kdtree_above'}
    defaults = {field.name: field.default for field in fields(StepParams)}
    switched_on = {key: value for key, value in newer.items() if value != defaults[key]}
    if switched_on:
        msg = f'the step of 130bc3a has no {sorted(switched_on)}; run the benchmark with them at their defaults.'
        raise SystemExit(msg)
    numbers = {key: value for key, value in asdict(params).items() if key in known and key != 'kdtree_above'}
    ends = np.array([0.0, tube.length_m])
    plan = old_step.PlanProfile(ends, np.full(2, 1 / 3.0), np.full(2, 0.2))
    step = old_step.SwarmStep(tube, old_step.StepParams(**numbers), r_a.size, plan=plan)
    step.r_a = r_a.copy()
    return step


def crowd(n: int, rng: np.random.Generator) -> tuple[VirtualTube, np.ndarray]:
    half_width = 0.5 * np.sqrt(n) + 2.0
    length = n / (2 * half_width - 2.0) + 10.0
    tube = VirtualTube(ArcPath((ArcPiece(length),)), WidthProfile(half_width, (WidthPart('constant', length),)))
    cols = int(2 * half_width - 2.0)
    k = np.arange(n)
    positions = np.vstack([5.0 + k // cols, -half_width + 1.5 + k % cols]).astype(float)
    return tube, positions + 0.2 * rng.standard_normal(positions.shape)


def stepper(tube: VirtualTube, params: StepParams, r_a: np.ndarray, *, warm_projection: bool = True) -> SwarmStep:
    """The swarm step flying a flat plan (3 m/s, 0.2 robots/m^2) from radii ``r_a``."""
    ends = np.array([0.0, tube.length_m])
    plan = PlanProfile(ends, np.full(2, 1 / 3.0), np.full(2, 0.2))
    step = SwarmStep(tube, params, r_a.size, plan=plan, warm_projection=warm_projection)
    step.r_a = r_a.copy()
    return step


def reference(params: StepParams) -> StepParams:
    """The reference configuration's numbers: the k-d tree at every N (it also flies cold, ``stepper``)."""
    return replace(params, kdtree_above=0)


def flying(step: Any, positions: np.ndarray, r_a: np.ndarray) -> partial[Any]:
    """One call of ``step`` per call, alternating between ``positions`` and their shift by one period (6 cm)."""
    frames = [positions, positions + np.array([[0.06], [0.0]])]
    count = [0]

    def call() -> Any:
        count[0] += 1
        step.r_a = r_a  # the same radii each call: every call times the same law
        return step(frames[count[0] % 2], 0.02)

    return partial(call)


def dense_avoidance(positions: np.ndarray, r_a: np.ndarray, params: StepParams) -> np.ndarray:
    """The barrier avoidance term from every pair, in blocks of rows."""
    n = positions.shape[1]
    out = np.zeros_like(positions)
    r_s = params.r_s_m
    for start in range(0, n, 512):
        rows = slice(start, min(n, start + 512))
        dx = positions[0, rows, None] - positions[0, None, :]
        dy = positions[1, rows, None] - positions[1, None, :]
        dist = np.hypot(dx, dy)
        np.fill_diagonal(dist[:, start : start + dist.shape[0]], np.inf)
        band = r_s + r_a[rows, None] * np.ones((1, n))
        gain = np.where(
            dist < band, barrier_gain(np.minimum(dist, 1e3), 2 * r_s, 2 * r_s, band, params.avoidance_gain), 0.0
        )
        out[0, rows] = np.sum(gain * dx / dist, axis=1)
        out[1, rows] = np.sum(gain * dy / dist, axis=1)
    return out


def setup(n: int, rng: np.random.Generator) -> tuple[VirtualTube, np.ndarray, np.ndarray, StepParams]:
    """The crowd of n robots, their radii (r_a + up to 0.4 m) and the default step's numbers."""
    params = ControlParams().step_params(SwarmParams(n_robots=n))
    tube, positions = crowd(n, rng)
    return tube, positions, np.full(n, params.r_a_m) + rng.uniform(0.0, 0.4, n), params


def crossover(sizes: list[int], repeats: int) -> int | None:
    """Time the avoidance term with all pairs and with the k-d tree; print both; the first N where the tree wins."""
    rng = np.random.default_rng(1)
    print(f'{"N":>6} {"all pairs [ms]":>15} {"k-d tree [ms]":>14}')
    first = None
    for n in sizes:
        _, positions, r_a, params = setup(n, rng)
        pairs = replace(params, kdtree_above=n)
        t_pairs = 1e3 * timed(partial(avoidance_velocity, positions, r_a, pairs), repeats)[0]
        t_tree = 1e3 * timed(partial(avoidance_velocity, positions, r_a, reference(params)), repeats)[0]
        print(f'{n:>6} {t_pairs:>15.3f} {t_tree:>14.3f}')
        if first is None and t_tree < t_pairs:
            first = n
    return first


def peak_memory(n: int, steps: int) -> None:
    """Build n robots and run ``steps`` steps; print the median ms per step (wall clock, and the CPU time this
    process used, which other processes' load does not inflate) and this process's peak memory (MiB)."""
    tube, positions, r_a, params = setup(n, np.random.default_rng(0))
    step = stepper(tube, params, r_a)
    call = flying(step, positions, r_a)
    call()  # the cold first projection, the tube's tables
    t_step = 1e3 * timed(call, steps)[0]
    cpu = sorted(process_time_of(call) for _ in range(max(1, steps)))
    t_cpu = 1e3 * cpu[len(cpu) // 2]
    print(f'{t_step:.1f} {t_cpu:.1f} {peak_rss_mib():.0f}')


def peak_rss_mib() -> float:
    """This process's peak resident memory, MiB: Linux's VmHWM, which starts afresh at exec. (``ru_maxrss`` does
    not: a child started by a large parent reports the parent's peak, as this benchmark's big row once did.)"""
    try:
        for line in Path('/proc/self/status').read_text().splitlines():
            if line.startswith('VmHWM:'):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def process_time_of(call: Any) -> float:
    """The CPU time (s) this process spends in one call of ``call``."""
    start = time.process_time()
    call()
    return time.process_time() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--sizes', type=int, nargs='+', default=[20, 200, 1000, 2000, 10000])
    parser.add_argument('--repeats', type=int, default=5)
    parser.add_argument('--big', type=int, default=100_000, help='the large swarm (0: skip)')
    parser.add_argument('--crossover-sizes', type=int, nargs='+', default=[10, 20, 30, 40, 50, 60, 80, 100, 150, 200])
    parser.add_argument('--peak-memory', type=int, default=0, help=argparse.SUPPRESS)  # the big row's subprocess
    args = parser.parse_args()
    if args.peak_memory:
        peak_memory(args.peak_memory, args.repeats)
        return
    rng = np.random.default_rng(0)
    before = load_before(BEFORE_ISSUE)
    if isinstance(before, str):
        print(f'no {BEFORE_ISSUE} column: {before}')
    print(
        f'{"N":>6} {"step [ms]":>10} {BEFORE_ISSUE + " [ms]":>13} {"ratio":>7} {"|diff| [m/s]":>12} '
        f'{"reference [ms]":>15} {"ratio":>7} {"dense avoidance [ms]":>21} {"ratio":>7} {"|diff| [m/s]":>12}'
    )
    sizes, times = [], []
    for n in args.sizes:
        tube, positions, r_a, params = setup(n, rng)
        repeats = 20 * args.repeats if n < 1000 else args.repeats
        now = flying(stepper(tube, params, r_a), positions, r_a)
        reference_step = flying(stepper(tube, reference(params), r_a, warm_projection=False), positions, r_a)
        velocity = now().velocity  # warm-up: the tube's k-d tree and warm-start tables, the first (cold) projection
        reference_step()
        old = ' ' * 34
        if isinstance(before, str):
            t_step, t_ref = (1e3 * t for t in timed_together([now, reference_step], repeats))
        else:
            old_step = flying(stepper_before(before, tube, params, r_a), positions, r_a)
            diff = np.abs(old_step().velocity - velocity).max()
            t_step, t_ref, t_old = (1e3 * t for t in timed_together([now, reference_step, old_step], repeats))
            old = f'{t_old:>13.3f} {t_old / t_step:>6.2f}x {diff:>12.1e}'
        dense = ''
        if n <= DENSE_UP_TO:
            t_dense = 1e3 * timed(partial(dense_avoidance, positions, r_a, params), args.repeats // 2)[0]
            diff = np.abs(avoidance_velocity(positions, r_a, params) - dense_avoidance(positions, r_a, params)).max()
            dense = f'{t_dense:>21.2f} {t_dense / t_step:>6.1f}x {diff:>12.1e}'
        print(f'{n:>6} {t_step:>10.3f} {old} {t_ref:>15.3f} {t_ref / t_step:>6.2f}x {dense}')
        sizes.append(n)
        times.append(t_step)
    if args.big:
        cmd = [sys.executable, '-m', 'benchmarks.sim_bench', '--peak-memory', str(args.big), '--repeats', '3']
        t_big, t_cpu, rss = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.split()
        print(
            f'{args.big:>6} {float(t_big):>10.1f}   (CPU time {t_cpu} ms; peak memory of a process running it: {rss} MiB)'
        )
        sizes.append(args.big)
        times.append(float(t_big))
    big = np.array(sizes) >= 200
    if big.sum() >= 2:
        slope = np.polyfit(np.log(np.array(sizes)[big]), np.log(np.array(times)[big]), 1)[0]
        print(f'growth exponent of the step time for N >= 200: {slope:.2f} (N log N gives about 1.1)')
    print(f'\nneighbour search crossover (avoidance term alone; KDTREE_ABOVE = {KDTREE_ABOVE}):')
    first = crossover(args.crossover_sizes, 20 * args.repeats)
    print(f'the k-d tree is first faster at N = {first}' if first else 'the k-d tree is faster at none of these N')


if __name__ == '__main__':
    main()
