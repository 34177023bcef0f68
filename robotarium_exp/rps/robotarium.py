"""``rps.robotarium.Robotarium``: the V2 simulator's contract (``docs/robotarium.md`` §2-4).

* Construction with V2's keywords and defaults (``number_of_robots``, ``show_figure``, ``initial_conditions``,
  ``use_distance_sensors``, ``obstacles``, ``sim_in_real_time``, ``skip_initialization``, the ``show_*`` options),
  checked with V2's messages and V2's ``AssertionError``; what V2 does not check (more robots than charger slots,
  an initialization that never finishes) raises [`RobotariumError`][robotarium_exp.rps.errors.RobotariumError].
* Call order ``get_poses() -> set_velocities(ids, dxu) -> step()`` enforced with the messages rps users know.
* ``step()``: the verifier's counts (`ARobotarium._validate`), then per-wheel clipping, forward Euler at
  0.033 s, then the on-board sensors (and the distance sensors with ``use_distance_sensors=True``, which see the
  other robots and the ``obstacles``, M x 2 x 2 line segments; `robotarium_exp.rps.utilities.sensors`).
  ``debug()`` prints V2's summary and verdict.
* The initialization is V2's algorithm, step for step: robots start on charger slots drawn with Python's
  ``random`` and are driven to the initial conditions by V2's hybrid pose controller under a unicycle barrier
  certificate, with V2's deadlock escapes (random waypoints from ``np.random``). Those steps count towards the
  duration but are not validated. With the same ``random.seed`` and ``np.random.seed`` the draws are V2's draws.
  A host that runs the same start many times recalls the state it leaves (`robotarium_exp.rps.initialization_memo`).
* ``testbed_model`` (a name or a `TestbedModel`): what the real robots
  do to the commands and the poses. ``'ideal'`` (the default) is the simulator above, bit for bit and without an
  extra draw; with another model (``'fitted'``, ``'fitted:2'``) the clipped command drives the robots through the
  model's delay, lag, gains, bias and stalls (a stalled robot drives on, so its next pose jumps ahead),
  ``get_poses`` returns the poses with its noise, heading steps and stale repeats, and the verifier still counts
  the true poses. The initialization stays ideal; the model's per-robot
  draws are made when it ends (`robotarium_exp.rps.testbed_model`).

Randomness comes from ``random`` and ``np.random``, as in V2, so that a script's seeds (or ``rps_alias --seed``)
make a run reproducible.
"""

from __future__ import annotations

import time
import warnings
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.rps import initialization_memo as memo_state
from robotarium_exp.rps.errors import RobotariumError
from robotarium_exp.rps.robotarium_abc import ARobotarium
from robotarium_exp.rps.testbed_model import Testbed, TestbedModel
from robotarium_exp.rps.testbed_model import testbed_model as named_model
from robotarium_exp.rps.utilities.barrier_certificates import create_uni_barrier_certificate
from robotarium_exp.rps.utilities.controllers import create_pose_controller_hybrid
from robotarium_exp.rps.utilities.misc import (
    CHARGER_SLOTS,
    create_at_pose,
    generate_initial_poses,
    generate_random_poses,
)
from robotarium_exp.rps.utilities.sensors import simulate_distance_sensors

FloatArray = NDArray[np.float64]

INITIALIZATION_STEP_LIMIT = 60_000
"""Steps (33 simulated minutes) after which the initialization is declared stuck. V2 has no limit and hangs."""
DEADLOCK_STEPS = 5 * 30
DEADLOCK_EPSILON_M = 0.1


class Robotarium(ARobotarium):
    """A simulated V2 Robotarium. See the module docstring for the contract.

    Beyond V2: ``errors`` (the verifier's counts so far), ``iterations`` (steps taken, initialization included)
    and ``initialization_steps``. Unknown keywords are ignored with a warning (V2 ignores them silently).
    """

    def __init__(
        self,
        *,
        number_of_robots: int = -1,
        show_figure: bool = False,
        initial_conditions: FloatArray = np.array([]),  # noqa: B008 - V2's default, never mutated
        use_distance_sensors: bool = False,
        obstacles: FloatArray | None = None,
        sim_in_real_time: bool = True,
        skip_initialization: bool = False,
        show_arena_boundaries: bool = True,
        show_robot_patches: bool = True,
        show_distance_endpoints: bool = True,
        show_distance_rays: bool = False,
        show_obstacles: bool = True,
        testbed_model: str | TestbedModel = 'ideal',
        **unknown: Any,
    ) -> None:
        if unknown:
            warnings.warn(
                f'Robotarium() ignores the unknown keyword(s) {sorted(unknown)}, as V2 does; check the spelling.',
                stacklevel=2,
            )
        _check_arguments(number_of_robots, show_figure, sim_in_real_time, use_distance_sensors, initial_conditions)
        model = named_model(testbed_model)
        charger_poses = generate_initial_poses(
            number_of_robots,
            width=float(self.BOUNDARIES[1] - self.BOUNDARIES[0] - self.ROBOT_DIAMETER),
            height=float(self.BOUNDARIES[3] - self.BOUNDARIES[2] - self.ROBOT_DIAMETER),
        )
        if initial_conditions.size == 0:
            initial_conditions = generate_random_poses(number_of_robots, spacing=0.5, width=2.75, height=1.75)
        super().__init__(
            number_of_robots=number_of_robots,
            show_figure=show_figure,
            initial_conditions=charger_poses,
            use_distance_sensors=use_distance_sensors,
            obstacles=obstacles,
            show_arena_boundaries=show_arena_boundaries,
            show_robot_patches=show_robot_patches,
            show_distance_endpoints=show_distance_endpoints,
            show_distance_rays=show_distance_rays,
            show_obstacles=show_obstacles,
        )
        self.initial_conditions = np.asarray(initial_conditions, dtype=float).copy()
        self.sim_in_real_time = sim_in_real_time
        self._previous_render_time = time.perf_counter()
        self._called_step_already = True
        self._checked_poses_already = False
        self._errors: dict[str, int] = {}
        self._iteration, self.initialization_steps = 0, 0
        self._testbed: Testbed | None = None  # none while initializing: the initialization stays ideal
        self._moving = self._velocities  # what moved the robots in the last step: the command unless a model acts
        if skip_initialization:
            self._poses = self.initial_conditions.copy()
        else:
            memo_state.initialize_or_recall(self, INITIALIZATION_STEP_LIMIT)
            self.initialization_steps = self._iteration
        self.initializing = False
        self._testbed = None if model.is_ideal else Testbed(model, number_of_robots, self.TIME_STEP)

    @property
    def errors(self) -> dict[str, int]:
        """The verifier's counts so far, all three keys present."""
        keys = ('robots_outside_boundaries', 'robots_too_close', 'exceeded_actuator_limits')
        return {key: self._errors.get(key, 0) for key in keys}

    @property
    def iterations(self) -> int:
        """Steps taken, initialization included (what ``debug()`` turns into a duration)."""
        return self._iteration

    # ------------------------------------------------------------------ the initialization

    def initialize(self, initial_conditions: FloatArray) -> None:
        """Drive the robots from the chargers to ``initial_conditions``: V2's algorithm and draws.

        Each robot is driven by V2's hybrid pose controller under the unicycle barrier certificate. A robot that
        has not moved ``DEADLOCK_EPSILON_M`` within ``DEADLOCK_STEPS`` steps (and still has somewhere to go) is
        sent to a random waypoint within 0.25 m until it has moved; a fresh waypoint is drawn whenever that
        takes longer than ``DEADLOCK_STEPS`` again. Two of V2's quirks are kept because they shape its durations:
        the robots it treats as not yet initialized are those whose *index* is not in the arrived *mask*
        (``np.isin`` of indices against booleans: robot 0 is left out while any robot is still on its way, robot 1
        once any has arrived), and the hybrid controller's remembered phases restart whenever it is called for a
        single robot. The loop ends when the poses read at the start of a step are at the initial conditions.
        """
        print(f'Initializing {self.number_of_robots} robots to initial conditions...')
        n = self.number_of_robots
        barrier = create_uni_barrier_certificate()
        controller = create_pose_controller_hybrid(
            angular_velocity_limit=np.pi / 3.0, position_epsilon=0.03, position_error=0.05, rotation_error=0.1
        )
        at_pose = create_at_pose(position_error=0.05, rotation_error=0.2)
        x = self.get_poses()
        step = 0
        timers = np.zeros(n, dtype=int)
        last_deadlock_poses = x.copy()
        waypointing = np.zeros(n, dtype=bool)
        waypoints = generate_random_poses(n, spacing=0.4, width=2.75, height=1.75)

        self.step()
        while not at_pose(x, initial_conditions)[0]:
            if self._iteration > INITIALIZATION_STEP_LIMIT:
                raise _stuck()
            x = self.get_poses()
            dxu = controller(x, initial_conditions)
            arrived = at_pose(x, initial_conditions)[1]
            indices = np.arange(n)
            for i in indices[~np.isin(indices, arrived)]:  # V2's index-against-mask test, kept (see docstring)
                moved = np.hypot(*(last_deadlock_poses[:2, i] - x[:2, i]))
                if waypointing[i]:
                    dxu[:, i] = controller(x[:, i : i + 1], waypoints[:, i : i + 1])[:, 0]
                    if moved > DEADLOCK_EPSILON_M:
                        waypointing[i] = False
                    elif step - timers[i] > DEADLOCK_STEPS:
                        waypoints[:, i] = _escape_waypoint(x, i, self.BOUNDARIES)
                        timers[i] = step
                elif step - timers[i] > DEADLOCK_STEPS and moved < DEADLOCK_EPSILON_M:
                    waypointing[i] = True
                    waypoints[:, i] = _escape_waypoint(x, i, self.BOUNDARIES)
                    timers[i] = step
                elif (
                    moved > DEADLOCK_EPSILON_M
                    or np.hypot(*controller(x[:, i : i + 1], initial_conditions[:, i : i + 1])[:, 0]) <= 0.1
                ):
                    timers[i] = step
                    last_deadlock_poses[:, i] = x[:, i]
            step += 1
            self.set_velocities(indices, barrier(dxu, x))
            self.step()
        print('At initial conditions... Starting Experiment')

    # ------------------------------------------------------------------ the loop

    def get_poses(self) -> FloatArray:
        """A copy of the poses, 3xN [x; y; theta]; once per ``step()``."""
        if self._checked_poses_already:
            raise AssertionError('Can only call get_poses() once per call of step()!')
        self._called_step_already = False
        self._checked_poses_already = True
        poses: FloatArray = self._poses.copy()
        if self._testbed is not None:
            return self._testbed.observe(poses)
        return poses

    def step(self) -> None:
        """Count what the verifier counts, clip each wheel, integrate one time step, simulate the sensors."""
        if self._called_step_already:
            raise AssertionError('Make sure you call get_poses before calling step()!')
        self._called_step_already = True
        self._checked_poses_already = False
        self._errors = self._validate(self._errors)
        self._iteration += 1
        self._velocities = self._threshold(self._velocities)
        self._velocities_old = self._velocities.copy()
        self._moving = self._velocities if self._testbed is None else self._testbed.actuate(self._velocities)
        travel = self.TIME_STEP * self._moving[0]
        self._poses[0] += travel * np.cos(self._poses[2])
        self._poses[1] += travel * np.sin(self._poses[2])
        self._poses[2] += self.TIME_STEP * self._moving[1]
        self._poses[2] = np.arctan2(np.sin(self._poses[2]), np.cos(self._poses[2]))
        if self._distance_sensors_enabled:
            self._distances = simulate_distance_sensors(
                poses=self._poses,
                obstacles=self.obstacles,
                distance_sensors_orientation=self.DISTANCE_SENSORS_ORIENTATION,
                robot_diameter=self.ROBOT_DIAMETER,
                robot_center_offset=self.CENTER_OFFSET,
                distance_sensor_range=self.DISTANCE_SENSOR_RANGE,
                distance_sensor_error=self.DISTANCE_SENSOR_ERROR,
                distance_sensor_dropout_prob=self.DISTANCE_SENSOR_DROPOUT_PROB,
                distance_sensor_outlier_prob=self.DISTANCE_SENSOR_OUTLIER_PROB,
            )
            self._distance_endpoints = self._calculate_endpoints(self._distances)
        self.simulate_encoder_readings()
        self.simulate_accelerations()
        self.simulate_gyros()
        self.simulate_magnetometers()
        self.simulate_orientations()
        if self.show_figure:
            self._draw_robots()
            if not self.initializing and self._distance_sensors_enabled:
                self._draw_distances()
        if self.sim_in_real_time:
            remaining = self.TIME_STEP - (time.perf_counter() - self._previous_render_time)
            if remaining > 0:
                time.sleep(remaining)
            self._previous_render_time = time.perf_counter()

    # ------------------------------------------------------------------ V2's on-board sensor models (np.random)

    def simulate_encoder_readings(self) -> None:
        """Wheel revolutions in counts (28 per motor turn, gear ratio 100.37), noise growing with sqrt(counts)."""
        wheels = self._uni_to_diff(self._moving)
        delta = wheels * self.TIME_STEP * self.ENCODER_COUNTS_PER_REVOLUTION * self.MOTOR_GEAR_RATIO / (2 * np.pi)
        delta += self.ENCODER_NOISE_STD * np.sqrt(np.maximum(np.abs(delta), 1.0)) * np.random.randn(*delta.shape)
        self._encoders += np.round(delta)

    def simulate_accelerations(self) -> None:
        """Gravity and the centripetal term at the IMU's offset.

        V2 differences the commands against a copy taken in the same step, so its translational and tangential
        terms are zero; ours are too.
        """
        n = self.number_of_robots
        omega = self._velocities[1]
        imu = self.IMU_ORIENTATION
        dv = (self._velocities - self._velocities_old) / self.TIME_STEP
        self._accelerations = np.vstack(
            [dv[0] - dv[1] * imu[1] - omega**2 * imu[0], dv[1] * imu[0] - omega**2 * imu[1], np.full(n, -9.81)]
        )
        self._accelerations += self.ACCELEROMETER_NOISE_STDS[:, None] * np.random.randn(3, n)

    def simulate_gyros(self) -> None:
        n = self.number_of_robots
        noise = self.GYRO_NOISE_STDS[:, None] * np.random.randn(3, n)
        self._gyros = np.vstack([np.zeros(n), np.zeros(n), self._moving[1]]) + noise

    def simulate_magnetometers(self) -> None:
        n, theta = self.number_of_robots, self._poses[2]
        noise = self.MAGNETOMETER_NOISE_STDS[:, None] * np.random.randn(3, n)
        field = [self.MAGNETOMETER_XY_AVG * np.cos(theta), -self.MAGNETOMETER_XY_AVG * np.sin(theta)]
        self._magnetic_fields = np.vstack([*field, np.full(n, self.MAGNETOMETER_Z_AVG)]) + noise

    def simulate_orientations(self) -> None:
        """The heading in degrees, [0, 360), with noise."""
        noise = self.ORIENTATION_NOISE_STD * np.random.randn(self.number_of_robots)
        self._orientations = np.mod(np.degrees(self._poses[2]) + noise, 360.0)

    # ------------------------------------------------------------------ end of script

    def debug(self) -> None:
        """Print V2's summary and verdict."""
        print(f'Your simulation took approximately {self._iteration * self.TIME_STEP:.2f} real seconds to execute.\n')
        e = self.errors
        too_close, outside, actuator = (
            e['robots_too_close'],
            e['robots_outside_boundaries'],
            e['exceeded_actuator_limits'],
        )
        if too_close + outside == 0 and actuator == 0:
            print('No errors or warnings in your simulation!  Your script will run on the Robotarium!\n')
        elif too_close + outside == 0:
            share = 100 * actuator / max(self._iteration, 1)
            print('No hard errors detected, your script will run on the Robotarium!\n')
            print(
                f'WARNING: {actuator} out of {self._iteration} (~{share:.0f}%) timesteps had velocity command(s) '
                'exceed actuator limits.\n'
                '         A large percentage of exceeded actuator commands will cause noticeable\n'
                '         differences between this simulation and the physical Robotarium.'
            )
        else:
            print('Errors detected, your script will NOT run on the Robotarium!\n')
            print('Errors:')
            if too_close:
                print(f'\t Simulation had {too_close} time steps where robots were too close (potential collision).')
            if outside:
                print(f'\t Simulation had {outside} time steps where robots were outside boundaries.')
            print('\nPlease fix the noted errors in your simulation; otherwise, your experiment will be rejected.')


def _check_arguments(
    number_of_robots: int,
    show_figure: bool,
    sim_in_real_time: bool,
    use_distance_sensors: bool,
    initial_conditions: FloatArray,
) -> None:
    """V2's checks of the constructor's arguments, with its messages; and one of ours, the number of charger slots."""
    for name, value, kind in (
        ('NumberOfRobots', number_of_robots, 'an integer'),
        ('ShowFigure', show_figure, 'a boolean'),
        ('SimInRealTime', sim_in_real_time, 'a boolean'),
        ('UseDistanceSensors', use_distance_sensors, 'a boolean'),
    ):
        expected = int if kind == 'an integer' else bool
        if not isinstance(value, expected) or (expected is int and isinstance(value, bool)):
            msg = f'{name} must be {kind}. Received type {type(value).__name__}.'
            raise AssertionError(msg)
    if not isinstance(initial_conditions, np.ndarray):
        msg = f'InitialConditions must be a numpy ndarray. Received type {type(initial_conditions).__name__}.'
        raise AssertionError(msg)  # noqa: TRY004 - what V2's assert raises
    if not 0 <= number_of_robots <= 50:
        raise AssertionError('Number of robots must be >= 0 and <= 50')
    if number_of_robots > CHARGER_SLOTS:  # V2's draw of the slots would fail with a bare ValueError
        msg = (
            f'V2 places every robot on one of its {CHARGER_SLOTS} charger slots (skip_initialization or not), so it '
            f'runs at most {CHARGER_SLOTS} robots; {number_of_robots} were asked.'
        )
        raise RobotariumError(msg)
    if initial_conditions.size > 0 and (
        initial_conditions.shape != (3, number_of_robots) or not np.all(np.isfinite(initial_conditions))
    ):
        msg = (
            f'initial_conditions must be a 3 x {number_of_robots} array [x; y; theta] of finite values; '
            f'got shape {initial_conditions.shape}.'
        )
        raise RobotariumError(msg)


def _escape_waypoint(x: FloatArray, i: int, boundaries: FloatArray) -> FloatArray:
    """V2's deadlock escape for robot ``i`` at poses ``x``: a random waypoint within 0.25 m (np.random)."""
    xmin, xmax, ymin, ymax = boundaries
    return np.array(
        [
            np.random.uniform(low=min(x[0, i] + 0.25, xmax), high=max(x[0, i] - 0.25, xmin)),
            np.random.uniform(low=min(x[1, i] + 0.25, ymax), high=max(x[1, i] - 0.25, ymin)),
            np.random.uniform(low=-np.pi, high=np.pi),
        ]
    )


def _stuck() -> RobotariumError:
    """The error of an initialization that did not finish within ``INITIALIZATION_STEP_LIMIT`` steps."""
    msg = (
        f'the initialization did not bring the robots to their initial conditions within '
        f'{INITIALIZATION_STEP_LIMIT} steps (V2 would hang here); space the initial conditions at least '
        '0.4 m apart inside |x| <= 1.375, |y| <= 0.875 (documentation: On the Robotarium, §2.6).'
    )
    return RobotariumError(msg)
