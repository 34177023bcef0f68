"""Time per control step at N = 20 of the planned controller and the paper's baselines, on one swarm state.

    python -m benchmarks.baselines_bench [--repeats 20]

The state is the Table 1 swarm in its entry formation on scene C. NMPC solves every agent's problem every
0.1 s (5 control steps of 0.02 s) and holds its accelerations in between: its update is timed, and the per-step
cost is that update spread over the 5 steps.
"""

from __future__ import annotations

import argparse

import numpy as np

from benchmarks._timing import timed
from vtube_planning import load_scene
from vtube_planning.baselines.flocking import FlockingParams, flocking_command
from vtube_planning.baselines.nmpc import NmpcParams, NmpcSwarm
from vtube_planning.onboard import SwarmStep
from vtube_planning.planning.planner import plan_convex
from vtube_planning.swarm.formation import initial_formation


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--repeats', type=int, default=20)
    args = parser.parse_args()
    scene = load_scene('C')
    swarm, tube = scene.swarm, scene.tube
    plan = plan_convex(tube, swarm, scene.planning)
    positions = initial_formation(tube, swarm, np.random.default_rng(0), 0.05)
    projection = tube.project(positions)
    velocities = 2.0 * projection.tangent
    planned = SwarmStep(tube, scene.control.step_params(swarm), swarm.n_robots, plan=plan.profile)
    flocking = FlockingParams.scaled(swarm)
    t_planned, _ = timed(lambda: planned(positions, 0.02), args.repeats)
    t_flocking, _ = timed(
        lambda: flocking_command(positions, velocities, tube.project(positions), flocking), args.repeats
    )
    params = NmpcParams.for_swarm(swarm)

    def nmpc_update() -> None:
        NmpcSwarm(tube, params).command(positions, velocities, tube.project(positions), 0.02)

    t_nmpc, _ = timed(nmpc_update, max(3, args.repeats // 5))
    steps_per_update = round(params.update_s / 0.02)
    print(f'N = {swarm.n_robots}, one control step (median):')
    print(f'  planned controller (projection + law)   {1e3 * t_planned:9.3f} ms')
    print(f'  optimized flocking (projection + law)   {1e3 * t_flocking:9.3f} ms')
    print(
        f'  NMPC update (20 agents, IPOPT each)     {1e3 * t_nmpc:9.1f} ms, i.e. '
        f'{1e3 * t_nmpc / steps_per_update:.1f} ms per 0.02 s step'
    )


if __name__ == '__main__':
    main()
