"""Planning time and objective of every shipped scene: convex method, polynomial method, SLSQP reference.

Run from the repository root (it imports the SLSQP reference written in the tests):

    python -m benchmarks.plan_bench [--repeats 3] [--slsqp-intervals 120]

Columns: the convex method at a 0.1 m grid (scaled by L/60 on the small Robotarium tubes); the polynomial
(segmented cubic) method; the SLSQP reference on a coarser grid of K intervals beside the convex method on the
same grid (same formulation, so equal objectives are expected); the speed-up of convex over SLSQP there.
Times are medians over repeats, in one process; J is (p1) of the plan as used.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from functools import partial

from benchmarks._timing import timed
from tests.vtube_planning.slsqp_reference import slsqp_plan
from vtube_planning import list_scenes, load_scene
from vtube_planning.planning.plan import initial_conditions
from vtube_planning.planning.planner import plan_convex
from vtube_planning.planning.polynomial import plan_polynomial


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--repeats', type=int, default=3)
    parser.add_argument('--slsqp-intervals', type=int, default=120)
    args = parser.parse_args()
    k = args.slsqp_intervals
    print(
        f'{"scene":<21} {"step":>6} {"convex s":>9} {"J convex":>10} {"poly s":>7} {"J poly":>10} '
        f'{"SLSQP@K s":>10} {"J SLSQP":>10} {"convex@K s":>11} {"J convex@K":>11} {"speed-up":>9}'
    )
    for name in list_scenes():
        scene = load_scene(name)
        tube, swarm = scene.tube, scene.swarm
        step = 0.1 * tube.length_m / 60.0 if tube.length_m < 10.0 else 0.1
        fine = replace(scene.planning, grid_step_m=step)
        t_convex, convex = timed(partial(plan_convex, tube, swarm, fine), args.repeats)
        t_poly, poly = timed(partial(plan_polynomial, tube, swarm, scene.planning), args.repeats)
        v0, rho0 = initial_conditions(swarm, scene.planning)
        try:
            t_slsqp, (_, _, _, j_slsqp) = timed(
                partial(slsqp_plan, tube, swarm, scene.planning, k, v0=v0, rho0=rho0), 1
            )
        except RuntimeError as err:  # SLSQP's own failures are part of the comparison
            print(f'{name:<21} SLSQP reference failed at K = {k}: {err}')
            t_slsqp, j_slsqp = float('nan'), float('nan')
        coarse = replace(scene.planning, grid_step_m=tube.length_m / k)
        t_coarse, same = timed(partial(plan_convex, tube, swarm, coarse), args.repeats)
        print(
            f'{name:<21} {step:>6.4f} {t_convex:>9.3f} {convex.objective["total"]:>10.5f} {t_poly:>7.3f} '
            f'{poly.objective["total"]:>10.5f} {t_slsqp:>10.3f} {j_slsqp:>10.5f} {t_coarse:>11.3f} '
            f'{same.objective["total"]:>11.5f} {t_slsqp / t_coarse:>8.1f}x'
        )


if __name__ == '__main__':
    main()
