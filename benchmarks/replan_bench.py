"""Replanning online: time per replan at N = 20 on scene C, and flights that replan every 0.5 s after a robot fails.

    python -m benchmarks.replan_bench [--seeds 5] [--repeats 5]

1. The states a planned flight of scene C passes through, every 0.5 s (the working robots' mean arc length and
   forward speed, the measured density): the time of ``replan`` from each (median of repeats), beside planning the
   whole tube; the median and largest over the states, and how many were infeasible to plan from.
2. Flights of scene C in which robot 0 (front row) stops dead at half the tube: flown on the first plan, and
   replanning every 0.5 s (``SimConfig.replan_every_s``), same seeds, one process: the replans made, their median
   and largest wall time, those that found the state infeasible (the old plan is kept), and what the swarm did.
   The paired study with intervals is the campaign ``docs/replanning``.
"""

from __future__ import annotations

import argparse
import time
from functools import partial

import numpy as np

from benchmarks._timing import timed
from vtube_planning import load_scene
from vtube_planning.errors import PlanError
from vtube_planning.planning.plan import SwarmState
from vtube_planning.planning.planner import plan_convex, replan
from vtube_planning.swarm.faults import RobotFailure
from vtube_planning.swarm.simulate import SimConfig, simulate

EVERY_S = 0.5


def replan_times(repeats: int) -> None:
    scene = load_scene('C')
    tube, swarm = scene.tube, scene.swarm
    t_full, plan = timed(partial(plan_convex, tube, swarm, scene.planning), repeats)
    flight = simulate(tube, swarm, scene.control, plan=plan, config=SimConfig(seed=0))
    every = round(EVERY_S / 0.02)
    times, infeasible = [], 0
    for k in range(every, flight.t_s.size, every):
        l_now = flight.l_m[k]
        flying = l_now < tube.length_m
        start = max(0.0, float(l_now[flying].mean())) if flying.any() else tube.length_m
        if start > tube.length_m - 2 * scene.planning.grid_step_m:
            break
        state = SwarmState(start, float(flight.forward_speed_mps[k, flying].mean()), float(flight.density_per_m2[k]))
        try:
            times.append(timed(partial(replan, plan, state, tube), repeats)[0])
        except PlanError:
            infeasible += 1
    ms = 1e3 * np.array(times)
    print(
        f'scene C, N = {swarm.n_robots}, grid {scene.planning.grid_step_m} m: planning the whole tube '
        f'{1e3 * t_full:.1f} ms; replanning from {len(times) + infeasible} states of a planned flight (every '
        f'{EVERY_S} s): median {np.median(ms):.1f} ms, largest {ms.max():.1f} ms, {infeasible} infeasible'
    )


def failure_flights(seeds: int) -> None:
    scene = load_scene('C')
    tube, swarm = scene.tube, scene.swarm
    plan = plan_convex(tube, swarm, scene.planning)
    failure = RobotFailure(robot=0, at_m=0.5 * tube.length_m)
    print(
        f'{"seed":>4} {"replan":>6} {"sim [s]":>8} {"replans":>7} {"median [ms]":>11} {"max [ms]":>8} '
        f'{"infeasible":>10} {"robots through":>14} {"passing [s]":>11} {"min dist [m]":>12}'
    )
    for seed in range(seeds):
        for every in (0.0, EVERY_S):
            config = SimConfig(seed=seed, failure=failure, replan_every_s=every)
            started = time.perf_counter()
            result = simulate(tube, swarm, scene.control, plan=plan, config=config)
            wall = time.perf_counter() - started
            calls = result.meta.get('replans', [])
            done = [c['wall_ms'] for c in calls if not c['error']]
            m = result.metrics
            print(
                f'{seed:>4} {"yes" if every else "no":>6} {wall:>8.1f} {len(calls):>7} '
                f'{np.median(done) if done else float("nan"):>11.1f} {max(done, default=float("nan")):>8.1f} '
                f'{len(calls) - len(done):>10} {m.robots_passed:>7}/{m.robots_counted:<6} '
                f'{m.passing_time_s:>11.2f} {m.min_distance_m:>12.3f}'
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seeds', type=int, default=5)
    parser.add_argument('--repeats', type=int, default=5)
    args = parser.parse_args()
    replan_times(args.repeats)
    print()
    failure_flights(args.seeds)


if __name__ == '__main__':
    main()
