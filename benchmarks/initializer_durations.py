"""How long V2's initialization takes to bring a scene's swarm to its initial conditions, over seeds.

    python -m benchmarks.initializer_durations robotarium_trapezoid [--seeds 100] [--first 0] [--limit 15000]

The bundled simulator runs V2's initializer with V2's draws (``seed_rps``), so the distribution is V2's up to the
barrier QP's tolerance (``docs/robotarium.md`` §2.6). Prints the median, 90 % quantile and maximum duration in
simulated seconds, and the seeds that did not finish within ``--limit`` steps (V2 hangs on those).
"""

from __future__ import annotations

import argparse
import contextlib
import io

import numpy as np

import robotarium_exp.rps.robotarium as simulator
from robotarium_exp.errors import RobotariumError
from robotarium_exp.experiment import initial_conditions
from robotarium_exp.rps_alias import seed_rps
from vtube_planning import load_scene


def durations(ic: np.ndarray, seeds: range, limit: int) -> tuple[list[float], list[int]]:
    """Initialization durations (s) of the seeds that finish, and the seeds that do not within ``limit`` steps."""
    simulator.INITIALIZATION_STEP_LIMIT = limit
    done, stuck = [], []
    for seed in seeds:
        seed_rps(seed)
        try:
            with contextlib.redirect_stdout(io.StringIO()):  # V2's "Initializing..." lines
                r = simulator.Robotarium(
                    number_of_robots=ic.shape[1], show_figure=False, sim_in_real_time=False, initial_conditions=ic
                )
        except RobotariumError:
            stuck.append(seed)
            continue
        done.append(r.iterations * r.TIME_STEP)
    return done, stuck


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('scene')
    parser.add_argument('--seeds', type=int, default=100)
    parser.add_argument('--first', type=int, default=0)
    parser.add_argument('--limit', type=int, default=15000, help='steps before a run counts as hung')
    args = parser.parse_args()
    ic = initial_conditions(load_scene(args.scene))
    done, stuck = durations(ic, range(args.first, args.first + args.seeds), args.limit)
    q = np.quantile(done, [0.5, 0.9]) if done else [np.nan, np.nan]
    print(
        f'{args.scene}: {len(done)} of {args.seeds} seeds initialized; median {q[0]:.1f} s, 90 % {q[1]:.1f} s, '
        f'max {max(done, default=np.nan):.1f} s; not within {args.limit} steps: {stuck}'
    )


if __name__ == '__main__':
    main()
