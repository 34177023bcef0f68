"""``--sim-clock``: ``time.time()`` advances by the time step at each ``step()``, so wall-clock scripts repeat."""

from __future__ import annotations

import math
import sys
import time

import numpy as np
import pytest

from robotarium_exp import rps_alias
from robotarium_exp.rps.robotarium import Robotarium as V2Robotarium
from robotarium_exp.rps_classic.robotarium import Robotarium as ClassicRobotarium
from robotarium_exp.sim_clock import START_S, SimClock, ticking

TIMED_SCRIPT = """\
import time
import numpy as np
import rps.robotarium as robotarium
from rps.utilities.transformations import *
from rps.utilities.barrier_certificates import *

# Two robots steered by a wall-clock schedule: the heading command depends on time.time(), as many
# classic-era scripts do it (dt measured between loop iterations, a run of a fixed number of seconds)
N = 2
r = robotarium.Robotarium(number_of_robots=N, show_figure=False, sim_in_real_time=False,
                          initial_conditions=np.array([[-0.5, 0.5], [0.0, 0.0], [0.0, np.pi]]))
si_to_uni_dyn = create_si_to_uni_dynamics()
uni_barrier_cert = create_unicycle_barrier_certificate()

start = time.time()
last = start
elapsed = 0.0
iterations = 0
x = r.get_poses()
r.step()
while time.time() - start < 3:
    x = r.get_poses()
    now = time.time()
    dt = now - last
    last = now
    elapsed += dt
    t = now - start
    dxi = 0.1 * np.vstack((np.cos(t + np.arange(N)), np.sin(2 * t + np.arange(N))))
    dxu = uni_barrier_cert(si_to_uni_dyn(dxi, x), x)
    r.set_velocities(np.arange(N), dxu)
    r.step()
    iterations += 1

print(iterations, repr(elapsed), repr(float(x[0, 0])), repr(float(x[1, 1])))
r.call_at_scripts_end()
"""
"""A script in the style of the classic-era ones that time their control with ``time.time()``."""


def test_the_clock_moves_only_when_a_robotarium_steps_by_its_time_step() -> None:
    clock = SimClock()
    wall = time.time
    try:
        clock.install()
        assert time.time() == START_S and time.time() == START_S
        for cls, dt in ((V2Robotarium, V2Robotarium.TIME_STEP), (ClassicRobotarium, 0.033)):
            r = ticking(cls, clock)(
                number_of_robots=1, show_figure=False, sim_in_real_time=False, initial_conditions=np.zeros((3, 1))
            )
            before = time.time()
            r.get_poses()
            r.step()
            assert time.time() - before == pytest.approx(dt, abs=1e-12) and type(r).__name__ == 'Robotarium'
    finally:
        clock.uninstall()
    assert time.time is wall


@pytest.mark.usefixtures('clean_rps')
def test_a_wall_clock_script_gives_the_same_run_every_time(tmp_path, monkeypatch, capsys) -> None:
    script = tmp_path / 'timed.py'
    script.write_text(TIMED_SCRIPT, encoding='utf-8')
    wall = time.time
    outputs = []
    for _ in range(2):
        monkeypatch.setattr(sys, 'argv', ['rps_alias', '--classic', '--seed', '0', '--sim-clock', str(script)])
        rps_alias.main()
        captured = capsys.readouterr()
        assert captured.err.startswith('rps_alias: --sim-clock: time.time() starts at 0.0 s')
        outputs.append(captured.out.splitlines()[0])
        assert time.time is wall  # the machine's clock is back after the run
    assert outputs[0] == outputs[1]
    iterations, elapsed = outputs[0].split()[:2]
    steps = math.ceil(3 / 0.033 - 1e-9)  # steps until the clock reaches 3 s; the first is before the loop
    assert int(iterations) == steps - 1
    assert float(elapsed) == pytest.approx((steps - 1) * 0.033, abs=1e-9)
