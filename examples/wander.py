"""A plain rps user script: six robots drive loops and save their poses.

It uses only the API both Robotarium generations share, so it runs unchanged on the testbed's simulator (the PyPI
``robotarium-python-simulator``) and on the bundled one:

    python examples/wander.py poses.npy                                   # with the PyPI rps installed
    python -m robotarium_exp.rps_alias --classic examples/wander.py poses.npy   # on the bundled simulator

The commands stay inside both simulators' actuator models (|v| + (L/2)|omega| < 0.2 m/s), so the two runs must agree.
"""

import sys

import numpy as np
from rps import robotarium

N = 6
STEPS = 300
initial_conditions = np.array([[-1.0, -0.6, -0.2, 0.2, 0.6, 1.0], [0.0, 0.3, -0.3, 0.3, -0.3, 0.0], [0.0] * 6])
r = robotarium.Robotarium(
    number_of_robots=N, show_figure=False, sim_in_real_time=False, initial_conditions=initial_conditions.copy()
)
history = []
for k in range(STEPS):
    x = r.get_poses()
    history.append(np.array(x, copy=True))
    v = 0.08 + 0.02 * np.sin(0.05 * k + np.arange(N))
    omega = 0.8 + 0.3 * np.cos(0.03 * k + 2 * np.arange(N))  # always turning: small loops near the start
    r.set_velocities(np.arange(N), np.vstack([v, omega]))
    r.step()
np.save(sys.argv[1] if len(sys.argv) > 1 else 'wander_poses.npy', np.array(history))
r.call_at_scripts_end()
