"""Consensus on a graph: eight robots meet by each moving towards its neighbours on a cycle.

Each robot's control point (0.05 m ahead of its axle) follows the consensus law dx_i = sum over neighbours j of
(x_j - x_i), at most 0.08 m/s, on the cycle graph's Laplacian (``rps.utilities.graph``); a unicycle barrier
certificate keeps them apart as they gather, so they end in a tight cluster instead of one point. Prints the
spread (largest distance from the centroid) before and after, then the Robotarium's verdict.

    python -m robotarium_exp.rps_alias --seed 0 examples/consensus.py [--iterations N] [--show]
"""

import argparse

import numpy as np
from rps import robotarium
from rps.utilities.barrier_certificates import create_uni_barrier_certificate_with_boundary
from rps.utilities.graph import cycleGL, topological_neighbors
from rps.utilities.transformations import create_si_to_uni_mapping

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument('--iterations', type=int, default=1000, help='control steps after the initialization')
parser.add_argument('--show', action='store_true', help='draw the robots in real time')
args = parser.parse_args()

N = 8
SPEED = 0.08  # m/s at the control point: with d = 0.05 m, |v| + (L/2)|omega| stays under 0.2 m/s
r = robotarium.Robotarium(number_of_robots=N, show_figure=args.show, sim_in_real_time=args.show)
laplacian = cycleGL(N)
si_to_uni, uni_to_si_states = create_si_to_uni_mapping()
barrier = create_uni_barrier_certificate_with_boundary()


def spread(points):
    return float(np.hypot(*(points - points.mean(axis=1, keepdims=True))).max())


start = None
for _ in range(args.iterations):
    x = r.get_poses()
    xi = uni_to_si_states(x)
    start = spread(xi) if start is None else start
    dxi = np.zeros((2, N))
    for i in range(N):
        for j in topological_neighbors(laplacian, i):
            dxi[:, i] += xi[:, j] - xi[:, i]
    dxi *= np.minimum(1.0, SPEED / np.maximum(np.hypot(*dxi), 1e-9))  # within what the wheels realise
    r.set_velocities(np.arange(N), barrier(si_to_uni(dxi, x), x))
    r.step()

print(f'spread: {start:.3f} m at the start, {spread(uni_to_si_states(r.get_poses())):.3f} m at the end')
r.debug()
