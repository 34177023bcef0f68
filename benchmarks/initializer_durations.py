"""How long V2's initialization takes to bring a scene's swarm to its initial conditions, over seeds.

    python -m benchmarks.initializer_durations robotarium_trapezoid [--seeds 100] [--first 0] [--limit 15000]

Prints the median, 90 % quantile and maximum duration in simulated seconds, and the seeds that did not finish
within ``--limit`` steps (V2 hangs on those); `robotarium_exp.initializer` runs them.
"""

from __future__ import annotations

import argparse

import numpy as np

from robotarium_exp.experiment import initial_conditions
from robotarium_exp.initializer import initializer_durations
from robotarium_exp.scene import load_scene


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('scene')
    parser.add_argument('--seeds', type=int, default=100)
    parser.add_argument('--first', type=int, default=0)
    parser.add_argument('--limit', type=int, default=15000, help='steps before a run counts as stuck')
    args = parser.parse_args()
    ic = initial_conditions(load_scene(args.scene))
    sample = initializer_durations(ic, range(args.first, args.first + args.seeds), args.limit)
    done = sample.durations_s
    q = np.quantile(done, [0.5, 0.9]) if done else [np.nan, np.nan]
    print(
        f'{args.scene}: {len(done)} of {args.seeds} seeds initialized; median {q[0]:.1f} s, 90 % {q[1]:.1f} s, '
        f'max {max(done, default=np.nan):.1f} s; not within {args.limit} steps: {list(sample.stuck_seeds)}'
    )


if __name__ == '__main__':
    main()
