"""Per-step compute of the submission's control loop at N = 6 (target: under 5 ms on a 2-core machine).

    python -m benchmarks.submission_bench [--steps 300]

Builds the robotarium_curve submission and runs its own flight (the code inlined in the file) on the bundled
simulator, timing per step what the file computes between get_poses and set_velocities: control points, the swarm
step on the sampled tube, the barrier certificate (the PyPI simulator's cvxopt one, which is what the testbed's
rps runs, and the bundled DAQP one), the near-identity map and wheel scaling. The simulator's step is not timed.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from functools import partial

import numpy as np

from benchmarks._timing import timed
from robotarium_exp.rps.robotarium import ClassicRobotarium
from submission.builder import build


def loop_times(namespace: dict, certificate: Callable[..., np.ndarray], steps: int) -> list[float]:
    """Per-step seconds of the file's own flight (its inlined code) with ``certificate`` as the barrier."""
    data = namespace['DATA']
    n = int(data['n_robots'])
    r = ClassicRobotarium(
        number_of_robots=n, sim_in_real_time=False, initial_conditions=np.array(data['initial_conditions'])
    )
    flight = namespace['build_flight'](data, lambda dxi, x: certificate(np.array(dxi, copy=True), x))
    dt = float(data['time_step_s'])
    times = []
    for _ in range(steps):
        poses = r.get_poses()
        start = time.perf_counter()
        period = flight(poses, dt)
        times.append(time.perf_counter() - start)
        r.set_velocities(np.arange(n), period.dxu)
        r.step()
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--steps', type=int, default=300)
    args = parser.parse_args()
    namespace: dict = {}
    exec(compile(build('robotarium_curve').source, 'submission', 'exec'), namespace)  # noqa: S102 - our own build
    barrier = namespace['DATA']['barrier']
    boundary = np.array(barrier['arena_m'])
    radius, limit = barrier['safety_radius_m'], barrier['magnitude_limit_mps']
    from robotarium_exp.rps.utilities.barrier_certificates import create_si_barrier_certificate_with_boundary

    certificates = {
        'bundled (DAQP)': create_si_barrier_certificate_with_boundary(
            safety_radius=radius, magnitude_limit=limit, boundary_points=boundary
        )
    }
    try:
        from rps.utilities.barrier_certificates import create_single_integrator_barrier_certificate_with_boundary
    except ImportError:
        print('PyPI robotarium-python-simulator not installed: cvxopt certificate skipped')
    else:
        certificates['testbed rps (cvxopt)'] = create_single_integrator_barrier_certificate_with_boundary(
            safety_radius=radius, magnitude_limit=limit, boundary_points=boundary
        )
    print(f'{"certificate":<22} {"median [ms]":>12} {"95th pct [ms]":>14} {"max [ms]":>10}')
    for name, certificate in certificates.items():
        _, times = timed(partial(loop_times, namespace, certificate, args.steps), 1)
        ms = 1e3 * np.array(times)
        print(f'{name:<22} {np.median(ms):>12.3f} {np.percentile(ms, 95):>14.3f} {ms.max():>10.3f}')


if __name__ == '__main__':
    main()
