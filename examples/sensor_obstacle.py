"""Distance sensors and an obstacle: two robots cross the arena through a wall they only see with their sensors.

The arena has a wall (an ``obstacles`` segment the simulator draws and the distance sensors see; the verifier does
not know it). Each robot drives back and forth between two goals on either side of the wall. What its seven
sensors see (``get_distance_endpoints()``: the world points where the readings end) within 0.35 m pushes its
control point away and, turned by 90 degrees, along the obstacle, so that it slides round the wall's end instead
of stopping in front of it. Prints the closest a robot's centre came to the wall and how many goals were reached,
then the verdict.

    python -m robotarium_exp.rps_alias --seed 0 examples/sensor_obstacle.py [--iterations N] [--show]
"""

import argparse

import numpy as np
from rps import robotarium
from rps.utilities.barrier_certificates import create_uni_barrier_certificate_with_boundary
from rps.utilities.controllers import create_si_position_controller
from rps.utilities.transformations import create_si_to_uni_mapping

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument('--iterations', type=int, default=3000, help='control steps after the initialization')
parser.add_argument('--show', action='store_true', help='draw the robots and the sensor readings in real time')
args = parser.parse_args()

N = 2
SPEED = 0.08
REACH = 0.35  # m: sensed points nearer than this repel
WALL = np.array([[0.0, -0.3], [0.0, 0.3]])  # one segment from (0, -0.3) to (0, 0.3)
goals = [np.array([[-0.8, 0.8], [0.1, 0.1]]), np.array([[0.8, -0.8], [-0.1, -0.1]])]  # per robot, a goal per column
initial = np.array([[-0.8, 0.8], [0.1, -0.1], [0.0, np.pi]])

r = robotarium.Robotarium(
    number_of_robots=N,
    show_figure=args.show,
    sim_in_real_time=args.show,
    initial_conditions=initial,
    use_distance_sensors=True,
    obstacles=WALL[None],
)
si_to_uni, uni_to_si_states = create_si_to_uni_mapping()
to_goal = create_si_position_controller(velocity_magnitude_limit=SPEED)
barrier = create_uni_barrier_certificate_with_boundary()


def distance_to_wall(points):
    """Distance of each point (2 x N) to the wall segment."""
    along = np.clip((points[1] - WALL[0, 1]) / (WALL[1, 1] - WALL[0, 1]), 0.0, 1.0)
    nearest = WALL[0][:, None] + along * (WALL[1] - WALL[0])[:, None]
    return np.hypot(*(points - nearest))


target = np.ones(N, dtype=int)
reached, closest = 0, np.inf
for _ in range(args.iterations):
    x = r.get_poses()
    closest = min(closest, float(distance_to_wall(x[:2]).min()))
    xi = uni_to_si_states(x)
    current = np.column_stack([goals[i][:, target[i]] for i in range(N)])
    dxi = to_goal(xi, current)
    seen = r.get_distance_endpoints()  # 2 x 7 x N, NaN where nothing was seen
    for i in range(N):
        points = seen[:, :, i][:, np.isfinite(seen[0, :, i])]
        away = xi[:, i : i + 1] - points
        gaps = np.hypot(*away)
        near = gaps < REACH
        push = (away[:, near] / gaps[near] * (1 / gaps[near] - 1 / REACH)).sum(axis=1)
        dxi[:, i] += 0.04 * (push + np.array([-push[1], push[0]]))  # away, and round (a quarter turn)
        if np.hypot(*(xi[:, i] - current[:, i])) < 0.05:
            target[i], reached = 1 - target[i], reached + 1
    dxi *= np.minimum(1.0, SPEED / np.maximum(np.hypot(*dxi), 1e-9))
    r.set_velocities(np.arange(N), barrier(si_to_uni(dxi, x), x))
    r.step()

print(f'closest to the wall: {closest:.3f} m; goals reached: {reached}')
r.debug()
