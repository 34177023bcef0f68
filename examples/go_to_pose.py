"""Go to pose: five robots drive to random goal poses (position and heading) and stop there.

Goals from ``generate_random_poses`` (0.5 m apart), V2's hybrid pose controller (approach, then turn in place)
wrapped so that robots at their pose hold still (``create_pose_parking_controller_hybrid``), a unicycle barrier
certificate, and ``create_at_pose`` to stop when all have arrived. Prints how many arrived and when, then the
verdict.

    python -m robotarium_exp.rps_alias --seed 0 examples/go_to_pose.py [--iterations N] [--show]
"""

import argparse

import numpy as np
from rps import robotarium
from rps.utilities.barrier_certificates import create_uni_barrier_certificate_with_boundary
from rps.utilities.controllers import create_pose_parking_controller_hybrid
from rps.utilities.misc import create_at_pose, generate_random_poses

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument('--iterations', type=int, default=3000, help='most control steps after the initialization')
parser.add_argument('--show', action='store_true', help='draw the robots in real time')
args = parser.parse_args()

N = 5
goals = generate_random_poses(N, spacing=0.5, width=2.5, height=1.5)
r = robotarium.Robotarium(number_of_robots=N, show_figure=args.show, sim_in_real_time=args.show)
controller = create_pose_parking_controller_hybrid()
barrier = create_uni_barrier_certificate_with_boundary()
at_pose = create_at_pose()

steps = 0
while steps < args.iterations:
    x = r.get_poses()
    if at_pose(x, goals)[0]:
        break
    r.set_velocities(np.arange(N), barrier(controller(x, goals), x))
    r.step()
    steps += 1

arrived = int(at_pose(r.get_poses() if steps == args.iterations else x, goals)[1].sum())
print(f'at their goal poses: {arrived} of {N} after {steps * r.TIME_STEP:.1f} s')
r.debug()
