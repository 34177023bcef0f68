"""Classic ``rps.robotarium``: the ``Robotarium`` of the classic generation (``docs/robotarium.md`` §3).

* ``Robotarium(number_of_robots=-1, show_figure=True, sim_in_real_time=True, initial_conditions=np.array([]))``;
  robots start exactly at the initial conditions (random grid poses from ``np.random`` when none are given).
* Call order ``get_poses() -> set_velocities(ids, dxu) -> step()``, enforced with classic's messages.
* ``get_poses()`` returns the internal pose array itself; ``step()`` updates it in place: validation of the
  commands (`RobotariumABC._validate`), then forward Euler with the commands as ``set_velocities`` clipped
  them, headings rewrapped; with a figure, the drawing and (real time) a wait for the rest of the 0.033 s.
* ``call_at_scripts_end()`` prints classic's report: the duration rounded up to whole seconds, then the counts.
* ``testbed_model`` (keyword only, beyond classic; `robotarium_exp.rps.testbed_model`): ``'ideal'`` (the
  default) is the above, bit for bit; with another model the command, clipped per wheel as the testbed does, moves
  the robots through the model's delay, lag, gains and bias, and ``get_poses()`` returns a noisy copy of the poses
  (no longer the array itself); the validation counts the true poses.

Like classic's ``from rps.robotarium_abc import *``, this module also offers ``RobotariumABC``, ``np``, ``plt``,
``patches``, ``math`` and ``time``.
"""

from __future__ import annotations

import math
import time
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import patches

from robotarium_exp.rps.testbed_model import Testbed, TestbedModel
from robotarium_exp.rps.testbed_model import testbed_model as named_model
from robotarium_exp.rps_classic.robotarium_abc import FloatArray, RobotariumABC

__all__ = ['Robotarium', 'RobotariumABC', 'math', 'np', 'patches', 'plt', 'time']


class Robotarium(RobotariumABC):
    """The classic simulated Robotarium; see the module docstring for the contract."""

    def __init__(
        self,
        number_of_robots: int = -1,
        show_figure: bool = True,
        sim_in_real_time: bool = True,
        initial_conditions: FloatArray = np.array([]),  # noqa: B008 - classic's default, never mutated (empty)
        *,
        testbed_model: str | TestbedModel = 'ideal',
    ) -> None:
        model = named_model(testbed_model)
        super().__init__(number_of_robots, show_figure, sim_in_real_time, initial_conditions)
        self._testbed = None if model.is_ideal else Testbed(model, self.number_of_robots, self.time_step)
        self.previous_render_time = time.perf_counter()
        self.sim_in_real_time = sim_in_real_time
        self._called_step_already = True
        self._checked_poses_already = False
        self._errors: dict[str, Any] = {}
        self._iterations = 0

    def get_poses(self) -> FloatArray:
        """The poses, 3xN [x; y; theta]: the simulator's own array (updated in place by ``step()``); once per step."""
        if self._checked_poses_already:
            raise AssertionError('Can only call get_poses() once per call of step().')
        self._called_step_already = False
        self._checked_poses_already = True
        return self.poses if self._testbed is None else self._testbed.observe(self.poses.copy())

    def step(self) -> None:
        """Validate the commands, integrate one time step in place, redraw (and wait, in real time)."""
        if self._called_step_already:
            raise AssertionError('Make sure to call get_poses before calling step() again.')
        self._called_step_already = True
        self._checked_poses_already = False
        self._errors = self._validate()
        self._iterations += 1
        poses, v, omega = self.poses, self.velocities[0, :], self.velocities[1, :]
        if self._testbed is not None:  # the testbed clips each wheel, then its model acts
            wheels = np.clip(self._uni_to_diff(self.velocities), -self.max_wheel_velocity, self.max_wheel_velocity)
            v, omega = self._testbed.actuate(self._diff_to_uni(wheels))
        poses[0, :] = poses[0, :] + self.time_step * np.cos(poses[2, :]) * v
        poses[1, :] = poses[1, :] + self.time_step * np.sin(poses[2, :]) * v
        poses[2, :] = poses[2, :] + self.time_step * omega
        poses[2, :] = np.arctan2(np.sin(poses[2, :]), np.cos(poses[2, :]))
        if self.show_figure:
            if self.sim_in_real_time:
                remaining = self.time_step - (time.perf_counter() - self.previous_render_time)
                if remaining > 0:
                    time.sleep(remaining)
                self.previous_render_time = time.perf_counter()
            self._place_robots()
            self.figure.canvas.draw_idle()
            self.figure.canvas.flush_events()

    def call_at_scripts_end(self) -> None:
        """Print classic's report: the deployment time (iterations x 0.033 s, rounded up) and the counts, or the
        all-clear. Classic scripts end with it; the testbed needs it to run them."""
        print('##### DEBUG OUTPUT #####')
        seconds = math.ceil(self._iterations * 0.033)
        print(f'Your simulation will take approximately {seconds} real seconds when deployed on the Robotarium. \n')
        if not self._errors:
            print('No errors in your simulation! Acceptance of your experiment is likely!')
            return
        endings = {'boundary': '\n', 'collision': '\n', 'actuator': ''}  # classic's blank lines
        for kind, ending in endings.items():
            if kind in self._errors:
                print(f'\t Simulation had {self._errors[kind]} {self._errors[kind + "_string"]}{ending}')
