"""Per-step compute of the submission's control loop at N = 6 (target: under 5 ms on a 2-core machine).

    python -m benchmarks.submission_bench [--steps 300]

Builds each Robotarium submission and runs its own flight (the code inlined in the file) on the bundled
simulator, timing per step what the file computes between get_poses and set_velocities: control points, the swarm
step on the sampled tube, the safety filter (barrier rows and speed band, an exact least-distance QP solved with
scipy's NNLS), the speed-constrained map. The simulator's step is not timed.
"""

from __future__ import annotations

import argparse
import time
from functools import partial

import numpy as np

from benchmarks._timing import timed
from robotarium_exp.rps_classic.robotarium import Robotarium
from robotarium_exp.scene import load_scene
from submission.builder import build
from vtube_planning.planning.planner import plan_convex


def loop_times(namespace: dict, steps: int) -> list[float]:
    """Per-step seconds of the file's own flight (its inlined code, with its safety filter)."""
    data = namespace['FlightData'].from_plain(namespace['DATA'])
    n = data.n_robots
    r = Robotarium(  # the classic one: robots placed at the initial conditions
        number_of_robots=n,
        show_figure=False,
        sim_in_real_time=False,
        initial_conditions=np.array(data.initial_conditions),
    )
    flight = namespace['build_flight'](data)
    dt = data.time_step_s
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
    print(f'{"scene":<22} {"median [ms]":>12} {"95th pct [ms]":>14} {"max [ms]":>10}')
    for scene in ('robotarium_trapezoid', 'robotarium_curve'):
        namespace: dict = {}
        loaded = load_scene(scene)
        plan = plan_convex(loaded.tube, loaded.swarm, loaded.planning, scene=loaded.name)
        exec(compile(build(loaded, plan).source, 'submission', 'exec'), namespace)  # noqa: S102 - our own build
        _, times = timed(partial(loop_times, namespace, args.steps), 1)
        ms = 1e3 * np.array(times)
        print(f'{scene:<22} {np.median(ms):>12.3f} {np.percentile(ms, 95):>14.3f} {ms.max():>10.3f}')


if __name__ == '__main__':
    main()
