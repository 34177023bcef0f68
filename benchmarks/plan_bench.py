"""Planning time and objective of every shipped scene: the banded solver beside the cvxpy reference, accuracy
against the continuous optimum, and the other methods.

Run from the repository root (it imports the SLSQP reference written in the tests):

    python -m benchmarks.plan_bench [--repeats 5] [--slsqp-intervals 120] [--skip-others]

1. Speed: the convex method at a 0.1 m grid (scaled by L/60 on the small Robotarium tubes), three ways, interleaved
   in one process: *before*, the planner as it was before the banded solver (the cvxpy formulation, started from
   the slowest admissible profile); *cvxpy*, the reference formulation from the same start as the default (the
   fastest admissible profile); *banded*, the default. Median times, J before and now, their difference, the
   banded plan's certificate, and the speed-ups against both.
2. Accuracy (scenes A and C): J converges to the continuous optimum J* linearly in the grid step h (the halving
   ratios are printed), so J* is estimated by Richardson extrapolation 2 J(h/16) - J(h/8) from the default h.
   Printed: J at the default grid and its gap to J*, the uniform grid step that the first-order error model
   needs for a 0.05 % gap, and J with the default grid refined where the constraints bind (``refinement = 8``).
3. Other methods: the polynomial (segmented cubic) method; the SLSQP reference on a coarser grid of K intervals
   beside the convex method on the same grid (same formulation, so equal objectives are expected).
"""

from __future__ import annotations

import argparse
import itertools
from dataclasses import replace
from functools import partial

from benchmarks._timing import timed
from tests.support.slsqp_reference import slsqp_plan
from vtube_planning import list_scenes, load_scene
from vtube_planning.planning.constraints import initial_conditions
from vtube_planning.planning.plan import Plan
from vtube_planning.planning.planner import plan_convex
from vtube_planning.planning.polynomial import plan_polynomial

TARGET_GAP = 5e-4
"""The issue's bound on J's relative gap to the continuous optimum at the default grid."""


def speed(repeats: int) -> None:
    print(
        f'{"scene":<21} {"step":>6} {"before [ms]":>11} {"cvxpy [ms]":>10} {"banded [ms]":>11} {"J before":>13} '
        f'{"J banded":>13} {"|dJ|":>8} {"certificate":>11} {"vs before":>9} {"vs cvxpy":>8}'
    )
    for name in list_scenes():
        scene = load_scene(name)
        tube, swarm = scene.tube, scene.swarm
        step = 0.1 * tube.length_m / 60.0 if tube.length_m < 10.0 else 0.1
        fine = replace(scene.planning, grid_step_m=step)
        runs: dict[str, list[tuple[float, Plan]]] = {'before': [], 'cvxpy': [], 'banded': []}
        for _ in range(repeats):  # interleaved, so that a change of machine load hits all three alike
            runs['before'].append(
                timed(partial(plan_convex, tube, swarm, fine, formulation='cvxpy', start='slowest'), 1)
            )
            runs['cvxpy'].append(timed(partial(plan_convex, tube, swarm, fine, formulation='cvxpy'), 1))
            runs['banded'].append(timed(partial(plan_convex, tube, swarm, fine), 1))
        t = {key: sorted(time for time, _ in values)[repeats // 2] for key, values in runs.items()}
        before, banded = runs['before'][-1][1], runs['banded'][-1][1]
        j_before, j_banded = before.objective['total'], banded.objective['total']
        print(
            f'{name:<21} {step:>6.4f} {1e3 * t["before"]:>11.1f} {1e3 * t["cvxpy"]:>10.1f} {1e3 * t["banded"]:>11.1f} '
            f'{j_before:>13.9f} {j_banded:>13.9f} {abs(j_before - j_banded):>8.1e} {banded.max_violation:>11.1e} '
            f'{t["before"] / t["banded"]:>8.1f}x {t["cvxpy"] / t["banded"]:>7.1f}x'
        )


def accuracy(repeats: int) -> None:
    print(
        f'{"scene":<6} {"h [m]":>6} {"J(h)":>10} {"halving ratios":>18} {"J* (extrap.)":>12} {"gap":>8} '
        f'{"h for 0.05 %":>12} {"J refined":>10} {"gap":>8} {"grid":>5} {"refined [ms]":>12}'
    )
    for name in ('A', 'C'):
        scene = load_scene(name)
        tube, swarm, options = scene.tube, scene.swarm, scene.planning
        h = options.grid_step_m
        values = [plan_convex(tube, swarm, replace(options, grid_step_m=h / 2**i)).objective['total'] for i in range(5)]
        drops = [a - b for a, b in itertools.pairwise(values)]
        ratios = ' '.join(f'{a / b:.2f}' for a, b in itertools.pairwise(drops))
        optimum = 2.0 * values[4] - values[3]
        gap = values[0] / optimum - 1.0
        refined_options = replace(options, refinement=8)
        t_refined, refined = timed(partial(plan_convex, tube, swarm, refined_options), repeats)
        j_refined = refined.objective['total']
        print(
            f'{name:<6} {h:>6.3f} {values[0]:>10.5f} {ratios:>18} {optimum:>12.5f} {100 * gap:>7.3f}% '
            f'{h * TARGET_GAP / gap:>12.4f} {j_refined:>10.5f} {100 * (j_refined / optimum - 1):>7.3f}% '
            f'{refined.l_m.size - 1:>5} {1e3 * t_refined:>12.1f}'
        )


def others(repeats: int, k: int) -> None:
    print(
        f'{"scene":<21} {"poly s":>7} {"J poly":>10} {"SLSQP@K s":>10} {"J SLSQP":>10} {"convex@K s":>11} '
        f'{"J convex@K":>11} {"speed-up":>9}'
    )
    for name in list_scenes():
        scene = load_scene(name)
        tube, swarm = scene.tube, scene.swarm
        t_poly, poly = timed(partial(plan_polynomial, tube, swarm, scene.planning), repeats)
        v0, rho0 = initial_conditions(swarm, scene.planning)
        try:
            t_slsqp, (_, _, _, j_slsqp) = timed(
                partial(slsqp_plan, tube, swarm, scene.planning, k, v0=v0, rho0=rho0), 1
            )
        except RuntimeError as err:  # SLSQP's own failures are part of the comparison
            print(f'{name:<21} SLSQP reference failed at K = {k}: {err}')
            t_slsqp, j_slsqp = float('nan'), float('nan')
        coarse = replace(scene.planning, grid_step_m=tube.length_m / k)
        t_coarse, same = timed(partial(plan_convex, tube, swarm, coarse), repeats)
        print(
            f'{name:<21} {t_poly:>7.3f} {poly.objective["total"]:>10.5f} {t_slsqp:>10.3f} {j_slsqp:>10.5f} '
            f'{t_coarse:>11.3f} {same.objective["total"]:>11.5f} {t_slsqp / t_coarse:>8.1f}x'
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--repeats', type=int, default=5)
    parser.add_argument('--slsqp-intervals', type=int, default=120)
    parser.add_argument('--skip-others', action='store_true', help='leave out the polynomial and SLSQP table')
    args = parser.parse_args()
    speed(args.repeats)
    print()
    accuracy(args.repeats)
    if not args.skip_others:
        print()
        others(args.repeats, args.slsqp_intervals)


if __name__ == '__main__':
    main()
