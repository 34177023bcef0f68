"""Barrier certificate and full experiment: the bundled Robotarium tools beside the PyPI simulator's, one process.

    python -m benchmarks.robotarium_bench [--repeats 40] [--steps 60]

1. Time per certificate call for N = 6, 20, 50 robots in tight, independent random states: ours solved exactly
   (``use_qp_solver('exact')``: vectorised rows, exact pruning, DAQP) and as the testbed does (the default: cvxopt
   at the testbed's tolerances, every row) beside the PyPI simulator's cvxopt certificate
   (``create_single_integrator_barrier_certificate_with_boundary``) on the same states. Both are the
   single-integrator certificate with the arena boundary; ours also carries V2's speed polygon.
2. The same along a trajectory (the robots of the tight grid cross to the mirrored grid, 30 steps a second), where
   ours exact starts each call from the last call's active rows. Both tables give the largest difference of ours
   exact from DAQP solving the same QP, every row of it, from scratch (``least_distance``).
3. A full 6-robot tube experiment (robotarium_curve, planning and barrier on, no initialization phase) run with
   our Robotarium class beside the same experiment code with the PyPI ``Robotarium``.

The certificates take turns on each block of `BLOCK` states (so a change of the machine's load hits all of
them alike, while each solves its block with its own code and data in cache, as in a control loop of its own; turns
call by call timed mostly the cache misses of the fast certificate after the slow one), over `ROUNDS` passes
through the states, and each column is the median of its calls. The process
runs OpenBLAS and OpenMP on one thread (``OPENBLAS_NUM_THREADS`` and ``OMP_NUM_THREADS`` are set to 1 below, before
numpy is imported, unless already set): both sides use BLAS (numpy's for ours, cvxopt's own for theirs), and on
matrices this small a second thread only adds hand-offs, doubling the times whenever the other core is busy.
"""

from __future__ import annotations

import os

# before numpy is imported (see above)
for _variable in ('OPENBLAS_NUM_THREADS', 'OMP_NUM_THREADS'):
    os.environ.setdefault(_variable, '1')

import argparse
import time
from collections.abc import Callable

import numpy as np

from robotarium_exp.experiment import ExperimentConfig, run_experiment
from robotarium_exp.rps.robotarium import Robotarium
from robotarium_exp.rps.utilities.barrier_certificates import (
    Certificate,
    create_si_barrier_certificate_with_boundary,
    least_distance,
    use_qp_solver,
)
from robotarium_exp.rps.utilities.barrier_rows import barrier_rows
from robotarium_exp.scene import load_scene
from vtube_planning.planning.planner import plan_convex


def grid(n: int) -> np.ndarray:
    side = int(np.ceil(np.sqrt(n)))
    k = np.arange(n)
    return np.vstack([(k % side) * 0.2 - 0.1 * side, (k // side) * 0.2 - 0.1 * side])


def states(n: int, count: int, rng: np.random.Generator) -> list[tuple[np.ndarray, np.ndarray]]:
    base = grid(n)
    return [(base + 0.02 * rng.standard_normal(base.shape), rng.normal(0.0, 0.15, (2, n))) for _ in range(count)]


def trajectory(n: int, count: int, rng: np.random.Generator) -> list[tuple[np.ndarray, np.ndarray]]:
    """States of the grid's robots heading at 0.15 m/s for the mirrored grid, moved by the exact certificate."""
    x = grid(n) + 0.02 * rng.standard_normal((2, n))
    goals = -x
    certificate = create_si_barrier_certificate_with_boundary(safety_radius=0.17)
    previous = use_qp_solver('exact')
    cases = []
    for _ in range(count):
        heading = goals - x
        u = 0.15 * heading / np.maximum(np.hypot(*heading), 0.15) + 0.01 * rng.standard_normal((2, n))
        cases.append((x, u))
        x = x + 0.033 * certificate(u, x)
    use_qp_solver(previous)
    return cases


BLOCK = 10
"""States each certificate solves in a row before the next one takes them."""

ROUNDS = {6: 5, 20: 5, 50: 1}
"""Passes through the states per N: one at N = 50, where a cvxopt call takes about 80 ms."""


def interleaved_ms(certificates: dict[str, Callable], cases, rounds: int) -> tuple[dict[str, float], list[np.ndarray]]:
    """Median ms per call of each certificate, the certificates in turn on each `BLOCK` of states, ``rounds``
    times through the states; and the answers of ``'exact'`` (the last round's: its warm start runs on)."""
    times: dict[str, list[float]] = {name: [] for name in certificates}
    answers: list[np.ndarray] = []
    for _ in range(rounds):
        answers.clear()
        for start in range(0, len(cases), BLOCK):
            for name, certificate in certificates.items():
                solver = use_qp_solver('exact' if name == 'exact' else 'testbed')
                for x, u in cases[start : start + BLOCK]:
                    command = u.copy()
                    t0 = time.perf_counter()
                    answer = certificate(command, x)
                    times[name].append(time.perf_counter() - t0)
                    if name == 'exact':
                        answers.append(answer)
                use_qp_solver(solver)
    return {name: 1e3 * float(np.median(spent)) for name, spent in times.items()}, answers


def from_scratch_difference(certificate: Certificate, cases, answers: list[np.ndarray]) -> float:
    """The largest difference of the answers from DAQP solving the same QPs, every row, from scratch."""
    worst = 0.0
    for (x, u), answer in zip(cases, answers):
        a, b = barrier_rows(x, certificate.spec)
        cold = least_distance(u.reshape(-1, order='F'), a, b)
        if cold is not None:
            worst = max(worst, float(np.abs(answer - cold.reshape(u.shape, order='F')).max()))
    return worst


def table(title: str, cases_of, theirs) -> None:
    print(title)
    print(
        f'{"N":>4} {"ours exact [ms]":>16} {"ours testbed [ms]":>18} {"PyPI cvxopt [ms]":>17} {"ratio exact":>12} '
        f'{"max diff":>9}'
    )
    for n in (6, 20, 50):
        cases = cases_of(n)
        ours = create_si_barrier_certificate_with_boundary(safety_radius=0.17)
        testbed = create_si_barrier_certificate_with_boundary(safety_radius=0.17)
        median, answers = interleaved_ms({'exact': ours, 'testbed': testbed, 'theirs': theirs}, cases, ROUNDS[n])
        difference = from_scratch_difference(ours, cases, answers)
        print(
            f'{n:>4} {median["exact"]:>16.3f} {median["testbed"]:>18.3f} {median["theirs"]:>17.3f} '
            f'{median["theirs"] / median["exact"]:>11.1f}x {difference:>9.1e}'
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--repeats', type=int, default=40, help='independent states')
    parser.add_argument('--steps', type=int, default=60, help='states of the trajectory')
    args = parser.parse_args()
    from rps.robotarium import Robotarium as PypiRobotarium
    from rps.utilities.barrier_certificates import create_single_integrator_barrier_certificate_with_boundary

    rng = np.random.default_rng(0)
    theirs = create_single_integrator_barrier_certificate_with_boundary(safety_radius=0.17)
    table('independent states', lambda n: states(n, args.repeats, rng), theirs)
    table('along a trajectory', lambda n: trajectory(n, args.steps, rng), theirs)
    scene = load_scene('robotarium_curve')
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    config = ExperimentConfig()
    t0 = time.perf_counter()
    mine = run_experiment(Robotarium, scene, plan, config, robotarium_kwargs={'skip_initialization': True})
    t_mine = time.perf_counter() - t0
    t0 = time.perf_counter()
    pypi = run_experiment(PypiRobotarium, scene, plan, config)
    t_pypi = time.perf_counter() - t0
    print(
        f'experiment, 6 robots, {mine.arrays["t_s"].size} steps: ours {t_mine:.2f} s, with the PyPI Robotarium '
        f'{t_pypi:.2f} s ({pypi.arrays["t_s"].size} steps), ratio {t_pypi / t_mine:.2f}x'
    )


if __name__ == '__main__':
    main()
