"""``Robotarium``: the testbed's simulator contract for both API generations (``docs/robotarium.md`` §2-4).

* Construction: the V2 keywords (``number_of_robots``, ``show_figure``, ``sim_in_real_time``, ``initial_conditions``,
  ``skip_initialization``) or the classic positional signature ``Robotarium(N, show_figure, sim_in_real_time, ic)``.
* Call order ``get_poses() -> set_velocities(ids, dxu) -> step()`` enforced with the messages rps users know.
* ``step()``: validation of the raw commands counted as V2 counts it (robots outside the boundary per step; pairs
  closer than 0.135 m between centres shifted 0.025 m forward, per pair and step; steps with a wheel command over
  12.5 rad/s), then per-wheel clipping exactly as the testbed, then forward Euler at 0.033 s.
* End of script: ``debug()`` (V2 verdict lines) or ``call_at_scripts_end()`` (classic report).
* Constants in both spellings: ``TIME_STEP``, ``BOUNDARIES`` = [xmin, xmax, ymin, ymax] (V2) and ``time_step``,
  ``boundaries`` = [xmin, ymin, width, height] (classic). One robot model: the V2 GTernal (axle 0.11 m).
* Optional V2 initialization: robots start on the 22 charger slots and are driven to the initial conditions by a
  pose controller under a unicycle barrier certificate; those steps count towards the duration but are not
  validated. Headless by default; ``show_figure=True`` draws with matplotlib, imported then.

Randomness (charger slots, random initial conditions, deadlock breaking) comes from ``rng``.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.errors import RobotariumError
from robotarium_exp.rps.utilities.barrier_certificates import create_uni_barrier_certificate
from robotarium_exp.rps.utilities.controllers import create_pose_controller_hybrid
from robotarium_exp.rps.utilities.misc import create_at_pose, generate_initial_poses, generate_random_poses
from robotarium_exp.spec import ROBOTARIUM

FloatArray = NDArray[np.float64]

MAX_ROBOTS = 50
INITIALIZATION_STEP_LIMIT = 9000
"""Steps the initialization may take (about 300 s) before it is declared stuck."""


class Robotarium:
    """A simulated Robotarium. See the module docstring for the contract."""

    TIME_STEP = ROBOTARIUM.time_step_s
    MAX_LINEAR_VELOCITY = ROBOTARIUM.max_linear_speed_mps
    ROBOT_DIAMETER = ROBOTARIUM.robot_diameter_m
    WHEEL_RADIUS = ROBOTARIUM.wheel_radius_m
    BASE_LENGTH = ROBOTARIUM.base_length_m
    MAX_WHEEL_VELOCITY = ROBOTARIUM.max_wheel_speed_radps
    MAX_ANGULAR_VELOCITY = 2 * (WHEEL_RADIUS / ROBOT_DIAMETER) * (MAX_LINEAR_VELOCITY / WHEEL_RADIUS)
    COLLISION_DIAMETER = ROBOTARIUM.collision_diameter_m
    COLLISION_OFFSET = ROBOTARIUM.collision_offset_m
    BOUNDARIES = ROBOTARIUM.arena_m
    # V2's on-board sensor models (encoders, IMU, magnetometer, orientation): values and noise of its simulator
    ENCODER_COUNTS_PER_REVOLUTION = 28
    MOTOR_GEAR_RATIO = 100.37
    ENCODER_NOISE_STD = 0.25
    IMU_ORIENTATION = np.array([0.0594 - 0.00319, 0.0344628 - 0.0475, 0.0])
    ACCELEROMETER_NOISE_STDS = np.array([0.012929, 0.012127, 0.052979])
    GYRO_NOISE_STDS = np.array([0.001663, 0.001216, 0.002372])
    MAGNETOMETER_NOISE_STDS = np.array([3.275843, 2.365798, 5.232685])
    MAGNETOMETER_Z_AVG = -39.8594
    MAGNETOMETER_XY_AVG = 6.0712
    ORIENTATION_NOISE_STD = 0.310830

    def __init__(
        self,
        number_of_robots: int = -1,
        show_figure: bool = False,
        sim_in_real_time: bool = True,
        initial_conditions: FloatArray | None = None,
        *,
        skip_initialization: bool = False,
        rng: np.random.Generator | None = None,
    ) -> None:
        if isinstance(number_of_robots, bool) or not isinstance(number_of_robots, int):
            msg = (
                f'The number of robots used argument (number_of_robots) provided to create the Robotarium object '
                f'must be an integer type. Recieved type {type(number_of_robots).__name__!r}. Pass int(N).'
            )
            raise RobotariumError(msg)
        if not 0 <= number_of_robots <= MAX_ROBOTS:
            msg = (
                f'Requested {number_of_robots} robots to be used when creating the Robotarium object. The deployed '
                f'number of robots must be between 0 and {MAX_ROBOTS}.'
            )
            raise RobotariumError(msg)
        for name, flag in (
            ('show_figure', show_figure),
            ('sim_in_real_time', sim_in_real_time),
            ('skip_initialization', skip_initialization),
        ):
            if not isinstance(flag, bool):
                msg = f'{name} must be a bool; got {type(flag).__name__} {flag!r}.'
                raise RobotariumError(msg)
        ic = np.array([]) if initial_conditions is None else initial_conditions
        if not isinstance(ic, np.ndarray):
            msg = (
                f'The initial conditions array argument (initial_conditions) provided to create the Robotarium '
                f'object must be a numpy ndarray. Recieved type {type(ic).__name__!r}.'
            )
            raise RobotariumError(msg)
        self.number_of_robots = number_of_robots
        self.show_figure = show_figure
        self.sim_in_real_time = sim_in_real_time
        self.rng = rng if rng is not None else np.random.default_rng()
        if ic.size == 0:
            ic = generate_random_poses(number_of_robots, spacing=0.5, width=2.75, height=1.75, rng=self.rng)
        if ic.shape != (3, number_of_robots) or not np.all(np.isfinite(ic)):
            msg = (
                f'Initial conditions provided when creating the Robotarium object must of size 3xN, where N is '
                f'the number of robots used. Expected a 3 x {number_of_robots} array of finite values but '
                f'recieved {ic.shape}.'
            )
            raise RobotariumError(msg)
        self.initial_conditions = ic.astype(float).copy()
        self._velocities = np.zeros((2, number_of_robots))
        self._distances = np.full((7, number_of_robots), np.nan)  # no distance sensors simulated: NaN, as V2 off
        self._accelerations = np.zeros((3, number_of_robots))
        self._gyros = np.zeros((3, number_of_robots))
        self._magnetic_fields = np.zeros((3, number_of_robots))
        self._orientations = np.zeros(number_of_robots)
        self._encoders = np.zeros((2, number_of_robots))
        self._errors: dict[str, int] = {
            'robots_outside_boundaries': 0,
            'robots_too_close': 0,
            'exceeded_actuator_limits': 0,
        }
        self._iteration = 0
        self.initialization_steps = 0
        self._checked_poses_already = False
        self._called_step_already = True
        self._last_step_wall = time.perf_counter()
        self._figure: Any = None
        if skip_initialization or number_of_robots == 0:
            self.poses = self.initial_conditions.copy()
        else:
            self.poses = generate_initial_poses(number_of_robots, rng=self.rng)
            self._initialize(self.initial_conditions)
        if show_figure:
            self._draw_setup()

    # ------------------------------------------------------------------ classic spellings

    @property
    def time_step(self) -> float:
        return self.TIME_STEP

    @property
    def boundaries(self) -> list[float]:
        """Classic format [x_min, y_min, width, height]."""
        xmin, xmax, ymin, ymax = self.BOUNDARIES
        return [xmin, ymin, xmax - xmin, ymax - ymin]

    @property
    def robot_diameter(self) -> float:
        return self.ROBOT_DIAMETER

    @property
    def wheel_radius(self) -> float:
        return self.WHEEL_RADIUS

    @property
    def base_length(self) -> float:
        return self.BASE_LENGTH

    @property
    def max_linear_velocity(self) -> float:
        return self.MAX_LINEAR_VELOCITY

    @property
    def max_angular_velocity(self) -> float:
        return self.MAX_ANGULAR_VELOCITY

    @property
    def max_wheel_velocity(self) -> float:
        return self.MAX_WHEEL_VELOCITY

    @property
    def velocities(self) -> FloatArray:
        return self._velocities.copy()

    @property
    def errors(self) -> dict[str, int]:
        """The V2 validation counts so far (outside boundaries, too close, exceeded actuator limits)."""
        return dict(self._errors)

    @property
    def iterations(self) -> int:
        """Steps taken, initialization included (what ``debug()`` turns into a duration)."""
        return self._iteration

    # ------------------------------------------------------------------ the loop

    def get_poses(self) -> FloatArray:
        """A copy of the poses, 3xN [x; y; theta]; once per ``step()``."""
        if self._checked_poses_already:
            msg = 'Can only call get_poses() once per call of step()!'
            raise RobotariumError(msg)
        self._checked_poses_already = True
        self._called_step_already = False
        return self.poses.copy()

    def set_velocities(self, ids: Any, velocities: FloatArray) -> None:
        """Set unicycle commands [v; omega] (2xk) of the robots ``ids`` (V2 semantics; all ids for classic)."""
        velocities = np.asarray(velocities, dtype=float)
        if velocities.ndim != 2 or velocities.shape[0] != 2 or velocities.shape[1] > self.number_of_robots:
            msg = (
                f'velocities must be a 2xk array [v; omega] with k <= number_of_robots = {self.number_of_robots}; '
                f'got {velocities.shape}.'
            )
            raise RobotariumError(msg)
        if not np.all(np.isfinite(velocities)):
            msg = 'velocities must be finite; a NaN or inf command would stop the real robots.'
            raise RobotariumError(msg)
        target = np.arange(self.number_of_robots)[ids]
        if np.size(target) != velocities.shape[1]:
            msg = f'ids select {np.size(target)} robots but velocities has {velocities.shape[1]} columns.'
            raise RobotariumError(msg)
        self._velocities[:, target] = velocities

    def step(self) -> None:
        """Validate the commands, clip each wheel, integrate one time step."""
        if self._called_step_already:
            msg = 'Make sure you call get_poses before calling step()!'
            raise RobotariumError(msg)
        self._called_step_already = True
        self._checked_poses_already = False
        self._validate()
        self._advance()
        if self._figure is not None:
            self._draw_update()
        if self.sim_in_real_time:
            remaining = self.TIME_STEP - (time.perf_counter() - self._last_step_wall)
            if remaining > 0:
                time.sleep(remaining)
            self._last_step_wall = time.perf_counter()

    # ------------------------------------------------------------------ end of script

    def debug(self) -> dict[str, int]:
        """Print V2's summary and verdict; returns the counts."""
        print(f'Your simulation took approximately {self._iteration * self.TIME_STEP:.2f} real seconds to execute.')
        e = self._errors
        if e['robots_outside_boundaries'] or e['robots_too_close']:
            print('Errors detected, your script will NOT run on the Robotarium!')
            print(f'\t{e["robots_too_close"]} time steps with robots too close to each other.')
            print(f'\t{e["robots_outside_boundaries"]} time steps with robots outside the boundaries.')
            if e['exceeded_actuator_limits']:
                print(f'\t{e["exceeded_actuator_limits"]} time steps exceeding actuator limits.')
        elif e['exceeded_actuator_limits']:
            share = 100 * e['exceeded_actuator_limits'] / max(1, self._iteration)
            print('No hard errors detected, your script will run on the Robotarium.')
            print(
                f'Warning: {e["exceeded_actuator_limits"]} time steps ({share:.1f}%) exceeded the actuator limits; '
                'those commands were clipped per wheel.'
            )
        else:
            print('No errors or warnings in your simulation! Your script will run on the Robotarium!')
        return self.errors

    def call_at_scripts_end(self) -> dict[str, int]:
        """Print the classic report; returns the counts."""
        print('##### DEBUG OUTPUT #####')
        print(
            f'Your simulation will take approximately {math.ceil(self._iteration * self.TIME_STEP)} real seconds '
            'when deployed on the Robotarium. \n'
        )
        e = self._errors
        if any(e.values()):
            if e['robots_outside_boundaries']:
                print(
                    f'\t Simulation had {e["robots_outside_boundaries"]} iterations where robot(s) were outside the '
                    'boundaries.\n'
                )
            if e['robots_too_close']:
                print(f'\t Simulation had {e["robots_too_close"]} iterations where robot(s) collided.\n')
            if e['exceeded_actuator_limits']:
                print(
                    f'\t Simulation had {e["exceeded_actuator_limits"]} iterations where robot(s) exceeded '
                    'actuator limits.'
                )
        else:
            print('No errors in your simulation! Acceptance of your experiment is likely!')
        return self.errors

    # ------------------------------------------------------------------ internals

    def wheel_speeds(self, dxu: FloatArray) -> FloatArray:
        """(2v -/+ L omega) / (2 r), 2xN."""
        return np.vstack([2 * dxu[0] - self.BASE_LENGTH * dxu[1], 2 * dxu[0] + self.BASE_LENGTH * dxu[1]]) / (
            2 * self.WHEEL_RADIUS
        )

    def _threshold(self, dxu: FloatArray) -> FloatArray:
        """Clip each wheel to the limit independently (the testbed's actuator model; changes omega / v)."""
        wheels = np.clip(self.wheel_speeds(dxu), -self.MAX_WHEEL_VELOCITY, self.MAX_WHEEL_VELOCITY)
        r, length = self.WHEEL_RADIUS, self.BASE_LENGTH
        return np.vstack([r * (wheels[0] + wheels[1]) / 2, r / length * (wheels[1] - wheels[0])])

    def _validate(self) -> None:
        p = self.poses
        outside = ROBOTARIUM.outside_arena(p[:2])
        self._errors['robots_outside_boundaries'] += int(outside.any())
        if self.number_of_robots > 1:
            shifted = p[:2] + self.COLLISION_OFFSET * np.vstack([np.cos(p[2]), np.sin(p[2])])
            i, j = np.triu_indices(self.number_of_robots, k=1)
            close = np.hypot(*(shifted[:, i] - shifted[:, j])) <= self.COLLISION_DIAMETER
            self._errors['robots_too_close'] += int(close.sum())
        over = np.abs(self.wheel_speeds(self._velocities)) > self.MAX_WHEEL_VELOCITY
        self._errors['exceeded_actuator_limits'] += int(over.any())

    def _advance(self) -> None:
        self._iteration += 1
        dxu = self._threshold(self._velocities)
        theta = self.poses[2]
        self.poses = np.vstack(
            [
                self.poses[0] + self.TIME_STEP * np.cos(theta) * dxu[0],
                self.poses[1] + self.TIME_STEP * np.sin(theta) * dxu[0],
                np.arctan2(np.sin(theta + self.TIME_STEP * dxu[1]), np.cos(theta + self.TIME_STEP * dxu[1])),
            ]
        )
        self._simulate_sensors(dxu)

    def _simulate_sensors(self, dxu: FloatArray) -> None:
        """V2's on-board readings after a step, noise from ``np.random`` as V2 draws it.

        Encoders count wheel revolutions (28 counts x 100.37 gear ratio per turn) with noise growing with the
        square root of the counts. The accelerometer sees gravity and the centripetal term at the IMU's offset:
        V2 differences the commands against themselves, so its translational and tangential terms are zero,
        and so are ours. The gyro reads omega, the magnetometer a field rotating with the heading, the orientation
        the heading in degrees [0, 360).
        """
        n = self.number_of_robots
        delta = self.wheel_speeds(dxu) * self.TIME_STEP * self.ENCODER_COUNTS_PER_REVOLUTION * self.MOTOR_GEAR_RATIO
        delta /= 2 * np.pi
        delta += self.ENCODER_NOISE_STD * np.sqrt(np.maximum(np.abs(delta), 1.0)) * np.random.randn(*delta.shape)
        self._encoders += np.round(delta)
        omega = dxu[1]
        imu = self.IMU_ORIENTATION
        self._accelerations = np.vstack([-(omega**2) * imu[0], -(omega**2) * imu[1], np.full(n, -9.81)])
        self._accelerations += self.ACCELEROMETER_NOISE_STDS[:, None] * np.random.randn(3, n)
        self._gyros = np.vstack([np.zeros(n), np.zeros(n), omega]) + self.GYRO_NOISE_STDS[:, None] * np.random.randn(
            3, n
        )
        theta = self.poses[2]
        field = np.vstack(
            [
                self.MAGNETOMETER_XY_AVG * np.cos(theta),
                -self.MAGNETOMETER_XY_AVG * np.sin(theta),
                np.full(n, self.MAGNETOMETER_Z_AVG),
            ]
        )
        self._magnetic_fields = field + self.MAGNETOMETER_NOISE_STDS[:, None] * np.random.randn(3, n)
        degrees = np.degrees(theta) + self.ORIENTATION_NOISE_STD * np.random.randn(n)
        self._orientations = np.mod(degrees, 360.0)

    # ------------------------------------------------------------------ V2's sensor getters (copies)

    def get_distances(self) -> FloatArray:
        """Seven distance readings per robot (7xN): NaN without simulated distance sensors, as V2 returns them."""
        return self._distances.copy()

    def get_accelerations(self) -> FloatArray:
        return self._accelerations.copy()

    def get_gyros(self) -> FloatArray:
        return self._gyros.copy()

    def get_magnetic_fields(self) -> FloatArray:
        return self._magnetic_fields.copy()

    def get_orientations(self) -> FloatArray:
        return self._orientations.copy()

    def get_encoders(self) -> NDArray[np.int32]:
        return self._encoders.astype(np.int32)

    def _initialize(self, goals: FloatArray) -> None:
        """V2's initialization: from the chargers to the goals under a unicycle barrier certificate (not validated)."""
        controller = create_pose_controller_hybrid(
            angular_velocity_limit=math.pi / 3, position_epsilon=0.03, position_error=0.05, rotation_error=0.1
        )
        barrier = create_uni_barrier_certificate()
        at_pose = create_at_pose(position_error=0.05, rotation_error=0.2)
        progress_at = self.poses[:2].copy()
        stalled = np.zeros(self.number_of_robots, dtype=int)
        waypoints = goals.copy()
        for _ in range(INITIALIZATION_STEP_LIMIT):
            done, _ = at_pose(self.poses, goals)
            if done:
                self.initialization_steps = self._iteration
                return
            moved = np.hypot(*(self.poses[:2] - progress_at)) > 0.1
            arrived = np.hypot(*(self.poses[:2] - goals[:2])) <= 0.05
            progress_at[:, moved | arrived] = self.poses[:2, moved | arrived]
            stalled = np.where(moved | arrived, 0, stalled + 1)
            for k in np.flatnonzero(stalled > 150):  # deadlock breaking, as V2: a random nearby waypoint
                waypoints[:2, k] = self.poses[:2, k] + self.rng.uniform(-0.25, 0.25, 2)
                stalled[k] = 0
            reached = np.hypot(*(self.poses[:2] - waypoints[:2])) < 0.05
            waypoints[:, reached] = goals[:, reached]
            dxu = barrier(controller(self.poses, waypoints), self.poses)
            self._velocities = dxu
            self._advance()
        msg = (
            f'the initialization did not bring the robots to their initial conditions within '
            f'{INITIALIZATION_STEP_LIMIT} steps; space the initial conditions at least 0.4 m apart inside '
            '|x| <= 1.375, |y| <= 0.875 (docs/robotarium.md §2.6).'
        )
        raise RobotariumError(msg)

    def _draw_setup(self) -> None:
        import matplotlib.pyplot as plt
        from matplotlib.patches import Rectangle

        self._figure, self._axes = plt.subplots()
        xmin, xmax, ymin, ymax = self.BOUNDARIES
        self._axes.add_patch(Rectangle((xmin, ymin), xmax - xmin, ymax - ymin, fill=False))
        self._axes.set_xlim(xmin - 0.1, xmax + 0.1)
        self._axes.set_ylim(ymin - 0.1, ymax + 0.1)
        self._axes.set_aspect('equal')
        self._axes.set_axis_off()
        self._robots = self._axes.scatter(self.poses[0], self.poses[1], s=60, color='gold', edgecolors='k', zorder=3)
        self.figure, self.axes = self._figure, self._axes  # classic names
        self._fig, self._axes_handle = self._figure, self._axes  # V2 names

    def _draw_update(self) -> None:
        self._robots.set_offsets(self.poses[:2].T)
        self._figure.canvas.draw_idle()
        self._figure.canvas.flush_events()


class ClassicRobotarium(Robotarium):
    """The classic generation's behaviour: robots start exactly at the initial conditions (no charger drive)."""

    def __init__(
        self,
        number_of_robots: int = -1,
        show_figure: bool = False,
        sim_in_real_time: bool = True,
        initial_conditions: FloatArray | None = None,
        *,
        rng: np.random.Generator | None = None,
    ) -> None:
        super().__init__(
            number_of_robots, show_figure, sim_in_real_time, initial_conditions, skip_initialization=True, rng=rng
        )
