"""Barrier certificate and full experiment: the bundled Robotarium tools beside the PyPI simulator's, one process.

    python -m benchmarks.robotarium_bench [--repeats 20]

1. Time per certificate call for N = 6, 20, 50 robots in tight, trajectory-like states: ours solved exactly
   (``use_qp_solver('exact')``: vectorised rows, exact pruning, DAQP) and as the testbed does (the default: cvxopt
   at the testbed's tolerances, every row) beside the PyPI simulator's cvxopt certificate
   (``create_single_integrator_barrier_certificate_with_boundary``) on the same states. Both are the
   single-integrator certificate with the arena boundary; ours also carries V2's speed polygon.
2. A full 6-robot tube experiment (robotarium_curve, planning and barrier on, no initialization phase) run with
   our Robotarium class beside the same experiment code with the PyPI ``Robotarium``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from robotarium_exp.experiment import ExperimentConfig, run_experiment
from robotarium_exp.rps.robotarium import Robotarium
from robotarium_exp.rps.utilities.barrier_certificates import create_si_barrier_certificate_with_boundary, use_qp_solver
from vtube_planning import load_scene
from vtube_planning.planning.planner import plan_convex


def states(n: int, count: int, rng: np.random.Generator) -> list[tuple[np.ndarray, np.ndarray]]:
    side = int(np.ceil(np.sqrt(n)))
    k = np.arange(n)
    base = np.vstack([(k % side) * 0.2 - 0.1 * side, (k // side) * 0.2 - 0.1 * side])
    return [(base + 0.02 * rng.standard_normal(base.shape), rng.normal(0.0, 0.15, (2, n))) for _ in range(count)]


def median_ms(fun, cases) -> float:
    times = []
    for x, u in cases:
        t0 = time.perf_counter()
        fun(u.copy(), x)
        times.append(time.perf_counter() - t0)
    return 1e3 * float(np.median(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--repeats', type=int, default=20)
    args = parser.parse_args()
    from rps.robotarium import Robotarium as PypiRobotarium
    from rps.utilities.barrier_certificates import create_single_integrator_barrier_certificate_with_boundary

    rng = np.random.default_rng(0)
    print(f'{"N":>4} {"ours exact [ms]":>16} {"ours testbed [ms]":>18} {"PyPI cvxopt [ms]":>17} {"ratio exact":>12}')
    ours = create_si_barrier_certificate_with_boundary(safety_radius=0.17)
    theirs = create_single_integrator_barrier_certificate_with_boundary(safety_radius=0.17)
    for n in (6, 20, 50):
        cases = states(n, args.repeats, rng)
        t_testbed, t_theirs = median_ms(ours, cases), median_ms(theirs, cases)
        previous = use_qp_solver('exact')
        t_exact = median_ms(ours, cases)
        use_qp_solver(previous)
        print(f'{n:>4} {t_exact:>16.3f} {t_testbed:>18.3f} {t_theirs:>17.3f} {t_theirs / t_exact:>11.1f}x')
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
