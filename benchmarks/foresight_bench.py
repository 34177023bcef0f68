"""Time of one control period with the foresight against N: the swarm step alone (the law, as the paper flies it)
beside the swarm step followed by the foresight (`vtube_planning.swarm.foresight`), the controller of robots held
to (2)-(4).

The crowd flies as Table 1's swarm does in a tube: robots on a grid jittered by 0.2 m at the desired density
rho_d = 0.1989 robots/m^2 (2.24 m apart) in a straight tube sized to hold them, each flying along the tube at
3 m/s; the foresight checks every robot's command and overrides the ones it finds unsafe (the share is printed). Both are called in turn in one process (a
load that comes and goes slows them alike); prints the median milliseconds per period, their ratio, and whether the
goals hold: within 2x of the step alone at N = 20, under 50 ms at N = 10,000.

    python -m benchmarks.foresight_bench [--sizes 20 200 1000 10000] [--repeats 15]
"""

from __future__ import annotations

import argparse

import numpy as np

from benchmarks._timing import timed_together
from benchmarks.sim_bench import flying, stepper
from vtube_planning import ArcPath, ArcPiece, VirtualTube, WidthPart, WidthProfile
from vtube_planning.onboard import StepParams
from vtube_planning.params import ControlParams, SwarmParams
from vtube_planning.swarm.foresight import Foresight, default_horizon

GOAL_RATIO_AT_20 = 2.0
GOAL_MS_AT_10000 = 50.0


def crowd(n: int, rng: np.random.Generator) -> tuple[VirtualTube, np.ndarray, np.ndarray, StepParams]:
    """n robots at rho_d in a straight tube, their radii (r_a) and the default step's numbers."""
    swarm = SwarmParams(n_robots=n)
    spacing = 1.0 / np.sqrt(swarm.rho_d_per_m2)
    cols = max(1, int(np.sqrt(n)))
    half_width = 0.5 * cols * spacing + 1.0
    length = spacing * (n // cols + 1) + 20.0
    tube = VirtualTube(ArcPath((ArcPiece(length),)), WidthProfile(half_width, (WidthPart('constant', length),)))
    k = np.arange(n)
    grid = np.vstack([5.0 + spacing * (k // cols), -half_width + 1.0 + spacing * (0.5 + k % cols)])
    params = ControlParams().step_params(swarm)
    return tube, grid + 0.2 * rng.standard_normal(grid.shape), np.full(n, params.r_a_m), params


def row(n: int, repeats: int) -> tuple[float, float, float]:
    """Median ms of the step alone and of the step with the foresight, and the share of robots overridden."""
    tube, positions, r_a, params = crowd(n, np.random.default_rng(0))
    swarm = SwarmParams(n_robots=n)
    velocity = np.vstack([np.full(n, 3.0), np.zeros(n)])
    law = flying(stepper(tube, params, r_a), positions, r_a)
    foresight = Foresight(tube, swarm, horizon_s=default_horizon(swarm), acceleration_limits=True)
    guarded = flying(stepper(tube, params, r_a), positions, r_a)
    frames = [positions, positions + np.array([[0.06], [0.0]])]
    count = [0]

    def both() -> object:
        count[0] += 1
        result = guarded()
        return foresight(frames[count[0] % 2], velocity, result.velocity, 0.02)

    law()
    both()  # the cold first calls: projections, the foresight's tables
    calls = foresight.overridden
    t_law, t_both = timed_together([law, both], repeats)
    share = (foresight.overridden - calls) / (n * max(1, repeats))
    return 1e3 * t_law, 1e3 * t_both, share


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--sizes', type=int, nargs='+', default=[20, 200, 1000, 10000])
    parser.add_argument('--repeats', type=int, default=15)
    args = parser.parse_args()
    print(f'{"N":>6} {"law [ms]":>9} {"law + foresight [ms]":>21} {"ratio":>6} {"overridden":>11}')
    results = {}
    for n in args.sizes:
        t_law, t_both, share = row(n, args.repeats)
        results[n] = (t_law, t_both)
        print(f'{n:>6} {t_law:>9.3f} {t_both:>21.3f} {t_both / t_law:>5.2f}x {100 * share:>10.1f}%')
    if 20 in results:
        ratio = results[20][1] / results[20][0]
        verdict = 'holds' if ratio <= GOAL_RATIO_AT_20 else 'missed'
        print(f'goal: N = 20 within {GOAL_RATIO_AT_20:g}x of the step alone: {ratio:.2f}x, {verdict}')
    if 10000 in results:
        ms = results[10000][1]
        verdict = 'holds' if ms < GOAL_MS_AT_10000 else 'missed'
        print(f'goal: N = 10,000 under {GOAL_MS_AT_10000:g} ms per period: {ms:.1f} ms, {verdict}')


if __name__ == '__main__':
    main()
