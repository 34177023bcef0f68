"""What weighting the density term of the objective (p1) trades: time for density, on scene C.

    python -m benchmarks.density_weight [--scene C] [--weights 1,10,30,100,300] [--window 12,26]

With the paper's unweighted objective (mu = 1) the density term is worth about a hundredth of a second, so the
planner lets the density dip before the narrowing rather than slow down; a weight mu (`density_weight` under a
scene's `[planning]`) trades traversal time for density. For each weight the scene is planned with the convex
method and the table gives the slowest planned speed in a window of arc length (on scene C, 12-26 m: after the
start's acceleration, where (p7) binds before the narrowing), the lowest planned density before the tube first
reaches its narrowest, the traversal time, and the certificate (the largest relative violation of
(p2)-(p7); 0 means every constraint holds).
"""

from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from vtube_planning import load_scene, plan_convex


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.partition('\n')[0])
    parser.add_argument('--scene', default='C')
    parser.add_argument('--weights', default='1,10,30,100,300')
    parser.add_argument(
        '--window', default='12,26', help='the arc lengths [m] between which the slowest speed is taken'
    )
    args = parser.parse_args()
    scene = load_scene(args.scene)
    low, high = (float(x) for x in args.window.split(','))
    print(f'scene {scene.name}, per density weight mu: the slowest speed for l in [{low:g}, {high:g}] m, the lowest')
    print('density before the narrowest part, the traversal time and the certificate')
    print(f'{"mu":>6}  {"slowest [m/s]":>13}  {"lowest density [1/m^2]":>22}  {"time [s]":>9}  {"certificate":>11}')
    for text in args.weights.split(','):
        options = dataclasses.replace(scene.planning, density_weight=float(text))
        plan = plan_convex(scene.tube, scene.swarm, options, scene=scene.name)
        before = plan.l_m <= plan.l_m[np.argmin(plan.half_width_m)]  # up to where the tube first reaches its narrowest
        window = (plan.l_m >= low) & (plan.l_m <= high)
        worst = max(plan.certificate.values())
        print(
            f'{float(text):>6g}  {plan.speed_mps[window].min():>13.2f}  {plan.density_per_m2[before].min():>22.3f}'
            f'  {plan.time_s:>9.3f}  {worst:>11.1e}'
        )


if __name__ == '__main__':
    main()
