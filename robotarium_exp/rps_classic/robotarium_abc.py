"""Classic ``rps.robotarium_abc``: the robot constants, argument checks, figure, command clipping and validation.

The classic generation keeps its constants as instance attributes in lower case (``time_step``, ``boundaries`` as
[x_min, y_min, width, height], ``base_length`` 0.105 m, ...). Its behaviours that V2 changed, reproduced here
because scripts written for it can depend on them (``docs/robotarium.md`` §3):

* the poses *are* the initial-conditions array passed in (no copy), and are later updated in place;
* ``set_velocities(ids, velocities)`` ignores ``ids``, clips |v| to 0.2 m/s and |omega| to 3.64 rad/s *in the
  caller's array*, and keeps that very array as the command; the wheels are never clipped;
* ``_validate`` counts, per step, every robot outside the arena and every pair whose centres are 0.11 m or less
  apart (plain centres, no forward shift), and each step with a wheel command above 12.5 rad/s, into one dictionary
  that every instance in the process shares (classic's mutable default argument), so counts carry over from one
  simulation to the next in the same process.

Misuse raises ``AssertionError``, exactly as classic's ``assert`` does, with classic's message text (typos included, so that scripts and logs read the same).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import patches
from numpy.typing import NDArray

from robotarium_exp.rps.errors import require
from robotarium_exp.rps_classic.utilities import misc

FloatArray = NDArray[np.float64]

SHARED_ERRORS: dict[str, Any] = {}
"""The validation counts of every classic Robotarium in this process (classic's shared default dictionary)."""

ERROR_TEXTS = {
    'boundary': 'iteration(s) robots were outside the boundaries.',
    'collision': 'iteration(s) where robots collided.',
    'actuator': 'iteration(s) where the actuator limits were exceeded.',
}
"""The text classic stores next to each count (``errors[kind + '_string']``) and prints in its report."""


def _check_arguments(
    number_of_robots: int, show_figure: bool, sim_in_real_time: bool, initial_conditions: FloatArray
) -> None:
    """Classic's checks of the constructor's arguments, with its messages."""
    require(
        isinstance(number_of_robots, int),
        'The number of robots used argument (number_of_robots) provided to create the Robotarium object must be '
        f'an integer type. Recieved type {type(number_of_robots).__name__!r}.',
    )
    require(
        isinstance(initial_conditions, np.ndarray),
        'The initial conditions array argument (initial_conditions) provided to create the Robotarium object '
        f'must be a numpy ndarray. Recieved type {type(initial_conditions).__name__!r}.',
    )
    require(
        isinstance(show_figure, bool),
        'The display figure window argument (show_figure) provided to create the Robotarium object must be '
        f'boolean type. Recieved type {type(show_figure).__name__!r}.',
    )
    require(  # classic names the type of show_figure in this message; so do we
        isinstance(sim_in_real_time, bool),
        'The simulation running at 0.033s per loop (sim_real_time) provided to create the Robotarium object must '
        f'be boolean type. Recieved type {type(show_figure).__name__!r}.',
    )
    require(
        0 <= number_of_robots <= 50,
        f'Requested {number_of_robots!r} robots to be used when creating the Robotarium object. The deployed '
        'number of robots must be between 0 and 50.',
    )
    if initial_conditions.size > 0:
        require(
            initial_conditions.shape == (3, number_of_robots),
            'Initial conditions provided when creating the Robotarium object must of size 3xN, where N is the '
            f'number of robots used. Expected a 3 x {number_of_robots!r} array but recieved a '
            f'{initial_conditions.shape[0]!r} x {initial_conditions.shape[1]!r} array.',
        )


class RobotariumABC(ABC):
    """The classic simulator's common part; `Robotarium` adds
    ``get_poses``, ``step`` and the report."""

    def __init__(
        self,
        number_of_robots: int = -1,
        show_figure: bool = True,
        sim_in_real_time: bool = True,
        initial_conditions: FloatArray = np.array([]),  # noqa: B008 - classic's default, never mutated (empty)
    ) -> None:
        _check_arguments(number_of_robots, show_figure, sim_in_real_time, initial_conditions)
        self.number_of_robots = number_of_robots
        self.show_figure = show_figure
        self.initial_conditions = initial_conditions
        self.boundaries = [-1.6, -1, 3.2, 2]
        self.file_path = None
        self.current_file_size = 0
        self.time_step = 0.033
        self.robot_diameter = 0.11
        self.wheel_radius = 0.016
        self.base_length = 0.105
        self.max_linear_velocity = 0.2
        self.max_angular_velocity = (
            2 * (self.wheel_radius / self.robot_diameter) * (self.max_linear_velocity / self.wheel_radius)
        )
        self.max_wheel_velocity = self.max_linear_velocity / self.wheel_radius
        self.robot_radius = self.robot_diameter / 2
        self.velocities = np.zeros((2, number_of_robots))
        self.poses = initial_conditions  # the caller's array itself, as classic
        if initial_conditions.size == 0:
            self.poses = misc.generate_initial_conditions(number_of_robots, spacing=0.2, width=2.5, height=1.5)
        self.left_led_commands: list[Any] = []
        self.right_led_commands: list[Any] = []
        self.figure: Any = []
        self.axes: Any = []
        self.chassis_patches: list[Any] = []
        self.left_led_patches: list[Any] = []
        self.right_led_patches: list[Any] = []
        self.left_wheel_patches: list[Any] = []
        self.right_wheel_patches: list[Any] = []
        if show_figure:
            self._draw_setup()

    # ------------------------------------------------------------------ commands

    def set_velocities(self, ids: Any, velocities: FloatArray) -> None:
        """Keep ``velocities`` (2xN [v; omega], all robots; ``ids`` is ignored) as the command, after clipping |v| to
        ``max_linear_velocity`` and |omega| to ``max_angular_velocity`` in place, in the caller's array."""
        for row, limit in ((0, self.max_linear_velocity), (1, self.max_angular_velocity)):
            over = np.where(np.abs(velocities[row, :]) > limit)
            velocities[row, over] = limit * np.sign(velocities[row, over])
        self.velocities = velocities

    @abstractmethod
    def get_poses(self) -> FloatArray:
        """The robots' poses, 3xN."""

    @abstractmethod
    def step(self) -> None:
        """Advance the simulation one time step."""

    # ------------------------------------------------------------------ wheels and validation

    def _uni_to_diff(self, dxu: FloatArray) -> FloatArray:
        """Wheel speeds (left; right) of unicycle commands: (2 v -/+ L omega) / (2 r), L = ``base_length``."""
        v, omega = dxu[0, :], dxu[1, :]
        spread = self.base_length * omega
        return np.vstack([2 * v - spread, 2 * v + spread]) / (2 * self.wheel_radius)

    def _diff_to_uni(self, dxdd: FloatArray) -> FloatArray:
        """Unicycle commands of wheel speeds: v = r (left + right) / 2, omega = r (right - left) / L."""
        r = self.wheel_radius
        return np.vstack([r / 2 * (dxdd[0, :] + dxdd[1, :]), r / self.base_length * (dxdd[1, :] - dxdd[0, :])])

    def _validate(self, errors: dict[str, Any] | None = None) -> dict[str, Any]:
        """Add this step's violations to ``errors`` (by default the dictionary shared by the process) and return it.

        Per step: +1 per robot outside the arena, +1 per pair of centres 0.11 m or less apart, +1 if any commanded
        wheel speed exceeds the limit. A kind's text is stored with its first count.
        """
        errors = SHARED_ERRORS if errors is None else errors
        x, y = self.poses[0, :], self.poses[1, :]
        left, bottom, width, height = self.boundaries
        outside = (x < left) | (x > left + width) | (y < bottom) | (y > bottom + height)
        i, j = np.triu_indices(self.number_of_robots, k=1)
        gaps = np.hypot(x[i] - x[j], y[i] - y[j])
        wheels = self._uni_to_diff(self.velocities)
        counts = {
            'boundary': int(np.count_nonzero(outside)),
            'collision': int(np.count_nonzero(gaps <= self.robot_diameter)),
            'actuator': int(np.any(np.abs(wheels) > self.max_wheel_velocity)),
        }
        for kind, count in counts.items():
            if count == 0:
                continue
            if kind not in errors:
                errors[kind] = 0
                errors[kind + '_string'] = ERROR_TEXTS[kind]
            errors[kind] += count
        return errors

    # ------------------------------------------------------------------ figure

    def _draw_setup(self) -> None:
        """The arena and one square chassis per robot (with wheels and LEDs), in an interactive figure."""
        self.figure, self.axes = plt.subplots()
        self.axes.set_axis_off()
        for _ in range(self.number_of_robots):
            for kind, patch in self._robot_patches().items():
                getattr(self, kind).append(patch)
                self.axes.add_patch(patch)
        self._place_robots()
        left, bottom, width, height = self.boundaries
        self.boundary_patch = self.axes.add_patch(patches.Rectangle((left, bottom), width, height, fill=False))
        self.axes.set_xlim(left - 0.1, left + width + 0.1)
        self.axes.set_ylim(bottom - 0.1, bottom + height + 0.1)
        plt.ion()
        plt.show()
        plt.subplots_adjust(left=-0.03, right=1.03, bottom=-0.03, top=1.03, wspace=0, hspace=0)

    def _robot_patches(self) -> dict[str, Any]:
        """One robot's patches, by the name of the list that holds them (placed by `_place_robots`)."""
        radius = self.robot_radius
        return {
            'right_wheel_patches': patches.Circle((0, 0), 0.02, facecolor='k'),
            'left_wheel_patches': patches.Circle((0, 0), 0.02, facecolor='k'),
            'chassis_patches': patches.RegularPolygon(
                (0, 0), numVertices=4, radius=math.sqrt(2) * radius, facecolor='#FFD700', edgecolor='k'
            ),
            'left_led_patches': patches.Circle((0, 0), radius / 5, fill=False),
            'right_led_patches': patches.Circle((0, 0), radius / 5, fill=False),
        }

    def _place_robots(self) -> None:
        """Move every robot's patches to its pose: wheels on both sides, LEDs near the front edge."""
        x, y, theta = self.poses[0, :], self.poses[1, :], self.poses[2, :]
        heading = np.vstack([np.cos(theta), np.sin(theta)])
        side = np.vstack([-heading[1], heading[0]])  # to the robot's left
        centre = np.vstack([x, y])
        front = centre + 0.75 * self.robot_radius * heading
        places = {
            'left_wheel_patches': centre + self.robot_radius * side,
            'right_wheel_patches': centre - self.robot_radius * side,
            'left_led_patches': front + 0.015 * side,
            'right_led_patches': front - 0.04 * side,
        }
        for i in range(self.number_of_robots):
            chassis = self.chassis_patches[i]
            chassis.xy = (x[i], y[i])
            chassis.orientation = theta[i] + math.pi / 4
            for kind, centres in places.items():
                getattr(self, kind)[i].center = (centres[0, i], centres[1, i])
