"""The Robotarium as numbers: one frozen [`RobotariumSpec`][robotarium_exp.spec.RobotariumSpec], the single source of
every testbed constant.

The experiment, the submission builder and its check, the command line and the arena checks all read
`ROBOTARIUM`; the submitted file carries the values it needs as data. The numbers the bundled simulator
(`robotarium_exp.rps`) has too (time step, arena, robot model, collision rule) are read from it; values from
``docs/robotarium.md`` (V2 simulator and the testbed's verifier).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotarium_exp.errors import SpecError
from robotarium_exp.rps.robotarium_abc import ARENA, ARobotarium

Bounds = tuple[float, float, float, float]


@dataclass(frozen=True)
class RobotariumSpec:
    """The testbed: time step, arena, robot model, the verifier's rules, where initial conditions may lie.

    Attributes
    ----------
    time_step_s
        Control period of ``step()``.
    arena_m
        ``(x_min, x_max, y_min, y_max)``: a robot whose centre leaves it counts as outside (per step).
    max_linear_speed_mps, wheel_radius_m, base_length_m, robot_diameter_m
        The GTernal robot: the wheel speed limit is ``max_linear_speed_mps / wheel_radius_m``.
    collision_diameter_m, collision_offset_m
        The verifier's collision rule: two robots are too close when their centres, each shifted
        ``collision_offset_m`` forward along its heading, are at most ``collision_diameter_m`` apart.
    max_robots
        Robots on the hardware testbed.
    ic_spacing_m
        Initial conditions at least this far apart: what the V2 initialization reaches reliably.
    ic_box_m
        ``(|x|, |y|)`` bounds of initial conditions (the box the V2 simulator samples from).
    arena_margin_m
        What a submission keeps between the tube, its initial conditions and parking slots and the arena's edge.
    duration_factor
        The testbed stops a run that takes longer than this many times the duration the user declared.
    """

    time_step_s: float = ARobotarium.TIME_STEP
    arena_m: Bounds = ARENA
    max_linear_speed_mps: float = ARobotarium.MAX_LINEAR_VELOCITY
    wheel_radius_m: float = ARobotarium.WHEEL_RADIUS
    base_length_m: float = ARobotarium.BASE_LENGTH
    robot_diameter_m: float = ARobotarium.ROBOT_DIAMETER
    collision_diameter_m: float = ARobotarium.COLLISION_DIAMETER
    collision_offset_m: float = ARobotarium.COLLISION_OFFSET
    max_robots: int = 20
    ic_spacing_m: float = 0.4
    ic_box_m: tuple[float, float] = (1.375, 0.875)
    arena_margin_m: float = 0.05
    duration_factor: float = 1.5

    def __post_init__(self) -> None:
        xmin, xmax, ymin, ymax = self.arena_m
        if not (xmin < xmax and ymin < ymax):
            msg = (
                f'arena_m must be (x_min, x_max, y_min, y_max) with x_min < x_max and y_min < y_max; '
                f'got {self.arena_m}.'
            )
            raise SpecError(msg)
        for name in ('time_step_s', 'max_linear_speed_mps', 'wheel_radius_m', 'base_length_m', 'robot_diameter_m'):
            if not getattr(self, name) > 0:
                msg = f'{name} must be > 0; got {getattr(self, name)!r}.'
                raise SpecError(msg)

    @property
    def max_wheel_speed_radps(self) -> float:
        """Largest wheel speed, rad/s (12.5 for the GTernal)."""
        return self.max_linear_speed_mps / self.wheel_radius_m

    @property
    def arena_text(self) -> str:
        """The arena for messages: ``[-1.6, 1.6] x [-1, 1]``."""
        xmin, xmax, ymin, ymax = self.arena_m
        return f'[{xmin:g}, {xmax:g}] x [{ymin:g}, {ymax:g}]'

    def outside_arena(self, points_m: ArrayLike, margin_m: float = 0.0) -> NDArray[np.bool_]:
        """Which of (2, N) points lie outside the arena shrunk by ``margin_m``, (N,) bool."""
        points = np.asarray(points_m, dtype=float)
        xmin, xmax, ymin, ymax = self.arena_m
        m = margin_m
        outside: NDArray[np.bool_] = (
            (points[0] < xmin + m) | (points[0] > xmax - m) | (points[1] < ymin + m) | (points[1] > ymax - m)
        )
        return outside


ROBOTARIUM = RobotariumSpec()
"""The Robotarium of ``docs/robotarium.md``."""
