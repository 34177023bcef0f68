"""What padding the measured footprint by the current r_a instead of the initial one does to (a3) and the swarm.

    python -m benchmarks.density_padding [--seeds 10] [--sizes 20,40,80] [--scenes C,D]

The planned swarm flies each scene, size and seed twice, its density N / S measured with the footprint S padded by
the initial r_a (``density_padding = 'initial'``) and by the current mean r_a (``'current'``); paired differences
(current - initial) with 95 % bootstrap intervals of the minimum distance, the passing time, the density error
against the plan and the final mean r_a.
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np

from vtube_planning import load_scene
from vtube_planning.planning.planner import plan_convex
from vtube_planning.studies.stats import paired_difference
from vtube_planning.swarm.metrics import tracking_errors
from vtube_planning.swarm.simulate import SimConfig, simulate

METRICS = ('min distance [m]', 'passing time [s]', 'density error [1/m^2]', 'final mean r_a [m]')


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seeds', type=int, default=10)
    parser.add_argument('--sizes', default='20,40,80')
    parser.add_argument('--scenes', default='C,D')
    args = parser.parse_args()
    print(f'| scene | N | padding | {" | ".join(METRICS)} |')
    print('|---|---|---|' + '---|' * len(METRICS))
    for name in args.scenes.split(','):
        scene = load_scene(name)
        for n in (int(k) for k in args.sizes.split(',')):
            swarm = replace(scene.swarm, n_robots=n)
            plan = plan_convex(scene.tube, swarm, scene.planning, scene=scene.name)
            values = {}
            for padding in ('initial', 'current'):
                control = replace(scene.control, density_padding=padding)
                rows = []
                for seed in range(args.seeds):
                    r = simulate(scene.tube, swarm, control, plan=plan, config=SimConfig(seed=seed))
                    errors = tracking_errors(r.l_m, r.forward_speed_mps, r.density_per_m2, plan, scene.tube.length_m)
                    rows.append(
                        [
                            r.metrics.min_distance_m,
                            r.metrics.passing_time_s,
                            errors['density_tracking_mean_per_m2'],
                            float(r.r_a_m[-1].mean()),
                        ]
                    )
                values[padding] = np.array(rows)
                means = ' | '.join(f'{v:.3f}' for v in values[padding].mean(axis=0))
                print(f'| {name} | {n} | {padding} | {means} |')
            diffs = [paired_difference(values['current'][:, k], values['initial'][:, k]) for k in range(len(METRICS))]
            print(f'| {name} | {n} | current - initial | ' + ' | '.join(d.text(3) for d in diffs) + ' |')


if __name__ == '__main__':
    main()
