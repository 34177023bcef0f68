"""Flown minus planned passing time, for the centre's objective (p1) and the last-robot-out objective.

    python -m benchmarks.objective_gap [--scenes C,D] [--sizes 20,80] [--seeds 5]

Each scene is planned for each swarm size four ways: with the paper's objective (``objective = "centre"``, the
centre's traversal time), with the last-robot-out objective (``objective = "last_out"``, ``docs/theory.md`` §8.7:
the centre's time plus the swarm's half-extent N / (4 lambda rho) over the speed at the entrance and at the exit),
and, as controls of what the planned density does to the flown time, with the centre's objective and (p7) off
(``predictive_model = "none"``: no pre-expansion, the density stays near rho_d) and with the density weighted
(``density_weight = 100``: the plan slows before the narrowing to dip less). Each plan is flown with `vtube_planning.simulate` (the paper's robot model, the scene's
controller, default ``SimConfig``) on seeds 0..n-1. Per plan the table gives the centre's planned traversal time
``T_c``, the passing time the last-out model gives for that plan ``T_out`` (T_c + entry + exit half-extents), the
bottleneck model's ``T_neck`` (T_c + entry half-extent + the largest half-extent over the tube, N / (4 lambda rho v)
at the grid point of least throughput 2 lambda rho v: the column's time spread cannot shrink once made), the flown
passing time (first robot in to last robot out; mean [min, max] over the seeds) and the gap, flown minus what the
plan's own objective plans (T_c for the centre's, T_out for the last-out one), mean [min, max]; ``T_out gap`` is
flown minus T_out for every plan, so that the model is also judged on plans that were not optimised for it. The
collision pairs are summed over the seeds.
"""

from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from vtube_planning import load_scene, plan_convex, simulate
from vtube_planning.geometry.scene import Scene
from vtube_planning.params import SwarmParams
from vtube_planning.planning.last_out import last_out_terms
from vtube_planning.planning.plan import Plan
from vtube_planning.swarm.simulate import SimConfig

PLANS = (
    ('centre', {}),
    ('last_out', {'objective': 'last_out'}),
    ('centre, (p7) off', {'predictive_model': 'none'}),
    ('centre, mu = 100', {'density_weight': 100.0}),
)
"""The plans compared: a label and the planning options changed from the scene's."""


def models(plan: Plan, scene: Scene) -> tuple[float, float, float]:
    """The plan's centre time T_c, the last-out model's T_out and the bottleneck model's T_neck (s)."""
    ends = last_out_terms(scene.tube, plan.swarm, plan.l_m, plan.speed_mps, plan.density_per_m2)
    throughput = 2.0 * plan.half_width_m * plan.density_per_m2 * plan.speed_mps  # robots/s past each grid point
    neck = plan.swarm.n_robots / (2.0 * float(throughput.min()))
    return plan.time_s, plan.time_s + ends['entry_s'] + ends['exit_s'], plan.time_s + ends['entry_s'] + neck


def spread(values: list[float]) -> str:
    """Mean [min, max] of ``values``."""
    return f'{np.mean(values):6.2f} [{min(values):6.2f}, {max(values):6.2f}]'


def flights(scene: Scene, swarm: SwarmParams, plan: Plan, seeds: int) -> tuple[list[float], int]:
    """The passing times over seeds 0..seeds-1 (NaN when a robot did not pass) and the collision pairs summed."""
    times, pairs = [], 0
    for seed in range(seeds):
        metrics = simulate(scene.tube, swarm, scene.control, plan=plan, config=SimConfig(seed=seed)).metrics
        times.append(metrics.passing_time_s)
        pairs += metrics.collision_pairs
    return times, pairs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.partition('\n')[0])
    parser.add_argument('--scenes', default='C,D')
    parser.add_argument('--sizes', default='20,80')
    parser.add_argument('--seeds', type=int, default=5)
    args = parser.parse_args()
    print(f"seeds 0-{args.seeds - 1}, the paper's robot model, default SimConfig; times in s")
    head = f'{"scene":>5} {"N":>3}  {"plan":<16} {"T_c":>6} {"T_out":>6} {"T_neck":>6}  {"flown":^22}  {"gap":^22}'
    print(head + f'  {"T_out gap":^22}  pairs')
    for name in args.scenes.split(','):
        scene = load_scene(name)
        for size in (int(text) for text in args.sizes.split(',')):
            swarm = dataclasses.replace(scene.swarm, n_robots=size)
            for label, changes in PLANS:
                options = dataclasses.replace(scene.planning, **changes)
                plan = plan_convex(scene.tube, swarm, options, scene=scene.name)
                centre, out, neck = models(plan, scene)
                planned = out if options.objective == 'last_out' else centre
                flown, pairs = flights(scene, swarm, plan, args.seeds)
                gap, out_gap = [t - planned for t in flown], [t - out for t in flown]
                print(
                    f'{name:>5} {size:>3}  {label:<16} {centre:6.2f} {out:6.2f} {neck:6.2f}  {spread(flown)}  '
                    f'{spread(gap)}  {spread(out_gap)}  {pairs:>5}'
                )


if __name__ == '__main__':
    main()
