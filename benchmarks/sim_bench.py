"""Time of one control step of the swarm controller against N, beside a dense all-pairs evaluation of the same law.

A control step is one call of the swarm step (:class:`vtube_planning.swarm.step.SwarmStep`) as the simulator
makes it: project every robot onto the tube, evaluate the command (forward term, avoidance with a k-d tree, tube
keeping, saturation), measure the density and advance r_a by (a3) against a constant planned density. The dense reference computes the same avoidance term from all N^2 distances (in row blocks, to bound
memory). Robots sit on a jittered grid at about one robot per m^2 in a straight tube sized to hold them, so each
has a few neighbours, as in a flying swarm. Prints median milliseconds per step, the ratio, and the growth
exponent of the k-d tree step (slope of log time against log N).

    python -m benchmarks.sim_bench [--sizes 20 200 1000 2000 10000] [--repeats 5]
"""

from __future__ import annotations

import argparse
from functools import partial

import numpy as np

from benchmarks._timing import timed
from vtube_planning import ArcPath, ArcPiece, SwarmParams, VirtualTube, WidthPart, WidthProfile
from vtube_planning.swarm.control import ControlParams
from vtube_planning.swarm.step import PlanProfile, StepParams, SwarmStep, avoidance_velocity, barrier_gain


def crowd(n: int, rng: np.random.Generator) -> tuple[VirtualTube, np.ndarray]:
    half_width = 0.5 * np.sqrt(n) + 2.0
    length = n / (2 * half_width - 2.0) + 10.0
    tube = VirtualTube(ArcPath((ArcPiece(length),)), WidthProfile(half_width, (WidthPart('constant', length),)))
    cols = int(2 * half_width - 2.0)
    k = np.arange(n)
    positions = np.vstack([5.0 + k // cols, -half_width + 1.5 + k % cols]).astype(float)
    return tube, positions + 0.2 * rng.standard_normal(positions.shape)


def stepper(tube: VirtualTube, params: StepParams, r_a: np.ndarray) -> SwarmStep:
    """The swarm step flying a flat plan (3 m/s, 0.2 robots/m^2) from radii ``r_a``."""
    ends = np.array([0.0, tube.length_m])
    step = SwarmStep(tube, params, r_a.size, plan=PlanProfile(ends, np.full(2, 1 / 3.0), np.full(2, 0.2)))
    step.r_a = r_a.copy()
    return step


def dense_avoidance(positions: np.ndarray, r_a: np.ndarray, params: StepParams) -> np.ndarray:
    """The barrier avoidance term from every pair, in blocks of rows."""
    n = positions.shape[1]
    out = np.zeros_like(positions)
    r_s = params.r_s_m
    for start in range(0, n, 512):
        rows = slice(start, min(n, start + 512))
        dx = positions[0, rows, None] - positions[0, None, :]
        dy = positions[1, rows, None] - positions[1, None, :]
        dist = np.hypot(dx, dy)
        np.fill_diagonal(dist[:, start : start + dist.shape[0]], np.inf)
        band = r_s + r_a[rows, None] * np.ones((1, n))
        gain = np.where(
            dist < band, barrier_gain(np.minimum(dist, 1e3), 2 * r_s, 2 * r_s, band, params.avoidance_gain), 0.0
        )
        out[0, rows] = np.sum(gain * dx / dist, axis=1)
        out[1, rows] = np.sum(gain * dy / dist, axis=1)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--sizes', type=int, nargs='+', default=[20, 200, 1000, 2000, 10000])
    parser.add_argument('--repeats', type=int, default=5)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    swarm_base = SwarmParams()
    control = ControlParams()
    print(f'{"N":>6} {"step [ms]":>10} {"dense avoidance [ms]":>21} {"ratio":>7} {"max |diff| [m/s]":>17}')
    sizes, times = [], []
    for n in args.sizes:
        params = control.step_params(SwarmParams(n_robots=n, r_a_m=swarm_base.r_a_m))
        tube, positions = crowd(n, rng)
        r_a = np.full(n, params.r_a_m) + rng.uniform(0.0, 0.4, n)
        step = stepper(tube, params, r_a)
        step(positions, 0.02)  # warm-up: build the tube's k-d tree
        t_step = 1e3 * timed(partial(step, positions, 0.02), args.repeats)[0]
        t_dense = 1e3 * timed(partial(dense_avoidance, positions, r_a, params), args.repeats // 2)[0]
        diff = np.abs(avoidance_velocity(positions, r_a, params) - dense_avoidance(positions, r_a, params))
        print(f'{n:>6} {t_step:>10.2f} {t_dense:>21.2f} {t_dense / t_step:>6.1f}x {diff.max():>17.1e}')
        sizes.append(n)
        times.append(t_step)
    big = np.array(sizes) >= 200
    if big.sum() >= 2:
        slope = np.polyfit(np.log(np.array(sizes)[big]), np.log(np.array(times)[big]), 1)[0]
        print(f'growth exponent of the step time for N >= 200: {slope:.2f} (N log N gives about 1.1)')


if __name__ == '__main__':
    main()
