"""Leader and followers: a leader tours the corners of a rectangle, four followers keep 0.3 m apart in a chain.

The leader (robot 0) drives its control point to each waypoint in turn with ``create_si_position_controller``;
follower i moves towards robot i - 1 with dx_i = (|x_{i-1} - x_i|^2 - 0.3^2) (x_{i-1} - x_i) (a line graph),
at most 0.08 m/s, all under a unicycle barrier certificate. Prints the waypoints reached and the followers'
mean and worst distance error to their predecessor over the last half of the run, then the verdict.

    python -m robotarium_exp.rps_alias --seed 0 examples/leader_follower.py [--iterations N] [--show]
"""

import argparse

import numpy as np
from rps import robotarium
from rps.utilities.barrier_certificates import create_uni_barrier_certificate_with_boundary
from rps.utilities.controllers import create_si_position_controller
from rps.utilities.graph import lineGL, topological_neighbors
from rps.utilities.transformations import create_si_to_uni_mapping

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument('--iterations', type=int, default=3000, help='control steps after the initialization')
parser.add_argument('--show', action='store_true', help='draw the robots in real time')
args = parser.parse_args()

N = 5
GAP = 0.3
SPEED = 0.08
waypoints = np.array([[-1.0, 1.0, 1.0, -1.0], [0.5, 0.5, -0.5, -0.5]])
chain = lineGL(N)

r = robotarium.Robotarium(number_of_robots=N, show_figure=args.show, sim_in_real_time=args.show)
si_to_uni, uni_to_si_states = create_si_to_uni_mapping()
leader_controller = create_si_position_controller(velocity_magnitude_limit=SPEED)
barrier = create_uni_barrier_certificate_with_boundary()

target, reached, errors = 0, 0, []
for k in range(args.iterations):
    x = r.get_poses()
    xi = uni_to_si_states(x)
    if np.hypot(*(xi[:, 0] - waypoints[:, target])) < 0.1:
        target, reached = (target + 1) % waypoints.shape[1], reached + 1
    dxi = np.zeros((2, N))
    dxi[:, :1] = leader_controller(xi[:, :1], waypoints[:, target : target + 1])
    for i in range(1, N):
        ahead = min(topological_neighbors(chain, i))  # the predecessor in the chain
        gap = xi[:, ahead] - xi[:, i]
        dxi[:, i] = 10.0 * (gap @ gap - GAP**2) * gap
        if k >= args.iterations // 2:
            errors.append(abs(np.hypot(*gap) - GAP))
    dxi *= np.minimum(1.0, SPEED / np.maximum(np.hypot(*dxi), 1e-9))
    r.set_velocities(np.arange(N), barrier(si_to_uni(dxi, x), x))
    r.step()

print(
    f'waypoints reached: {reached}; follower distance error: mean {np.mean(errors):.3f} m, max {np.max(errors):.3f} m'
)
r.debug()
