"""Formation control: six robots take the shape of a hexagon of side 0.4 m, wherever they start.

Distance-based formation on a rigid graph (the hexagon's edges and its three long diagonals): each control point
moves along dx_i = sum over neighbours j of (|x_j - x_i|^2 - w_ij^2) (x_j - x_i), the gradient of the squared
distance errors, at most 0.08 m/s, under a unicycle barrier certificate. Prints the largest edge-length error at
the end, then the Robotarium's verdict.

    python -m robotarium_exp.rps_alias --seed 0 examples/formation.py [--iterations N] [--show]
"""

import argparse

import numpy as np
from rps import robotarium
from rps.utilities.barrier_certificates import create_uni_barrier_certificate_with_boundary
from rps.utilities.transformations import create_si_to_uni_mapping

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument('--iterations', type=int, default=1500, help='control steps after the initialization')
parser.add_argument('--show', action='store_true', help='draw the robots in real time')
args = parser.parse_args()

N = 6
SIDE = 0.4
SPEED = 0.08  # m/s at the control point: with d = 0.05 m, |v| + (L/2)|omega| stays under 0.2 m/s
GAIN = 10.0
corners = SIDE * np.vstack([np.cos(np.arange(N) * np.pi / 3), np.sin(np.arange(N) * np.pi / 3)])
weights = np.hypot(*(corners[:, :, None] - corners[:, None, :]))  # desired distances, N x N
edges = [(i, (i + 1) % N) for i in range(N)] + [(i, i + 3) for i in range(3)]  # rigid: sides and long diagonals

r = robotarium.Robotarium(number_of_robots=N, show_figure=args.show, sim_in_real_time=args.show)
si_to_uni, uni_to_si_states = create_si_to_uni_mapping()
barrier = create_uni_barrier_certificate_with_boundary()


def largest_error(points):
    return max(abs(np.hypot(*(points[:, i] - points[:, j])) - weights[i, j]) for i, j in edges)


for _ in range(args.iterations):
    x = r.get_poses()
    xi = uni_to_si_states(x)
    dxi = np.zeros((2, N))
    for i, j in edges:
        pull = GAIN * (np.sum((xi[:, j] - xi[:, i]) ** 2) - weights[i, j] ** 2) * (xi[:, j] - xi[:, i])
        dxi[:, i] += pull
        dxi[:, j] -= pull
    dxi *= np.minimum(1.0, SPEED / np.maximum(np.hypot(*dxi), 1e-9))
    r.set_velocities(np.arange(N), barrier(si_to_uni(dxi, x), x))
    r.step()

print(f'largest edge-length error: {largest_error(uni_to_si_states(r.get_poses())):.3f} m')
r.debug()
