"""``rps.robotarium_abc``: what every V2 Robotarium shares (``docs/robotarium.md`` §2-4).

`ARobotarium` holds the GTernal robot's constants, the state the testbed hands back (poses and the on-board
sensors' readings), ``set_velocities``, the per-wheel clipping of the actuators, the verifier's three counts and the
drawing. `robotarium_exp.rps.robotarium.Robotarium` adds the loop (``get_poses``, ``step``, ``debug``) and
the initialization. The constants are V2's (`robotarium_exp.spec` reads the testbed's numbers from here).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.rps.errors import RobotariumError

FloatArray = NDArray[np.float64]

ARENA = (-1.6, 1.6, -1.0, 1.0)
"""The arena, ``(x_min, x_max, y_min, y_max)`` in m: a robot whose centre leaves it is outside."""


class ARobotarium(ABC):
    """The V2 Robotarium's shared part: constants, state, actuator model, verifier counts, drawing."""

    TIME_STEP = 0.033
    MAX_LINEAR_VELOCITY = 0.2
    ROBOT_DIAMETER = 0.11
    WHEEL_RADIUS = 0.016
    BASE_LENGTH = 0.11
    COLLISION_DIAMETER = 0.135
    """The verifier's collision rule: two robots are too close when their centres, each shifted ``COLLISION_OFFSET``
    forward along its heading, are at most this far apart."""
    COLLISION_OFFSET = 0.025
    BOUNDARIES = np.array(ARENA)
    """[x_min, x_max, y_min, y_max] as an array, as V2 (so ``r.BOUNDARIES * 0.5`` works)."""
    CENTER_OFFSET = 0.01
    """How far ahead of the axle a robot's body (a disc of ``ROBOT_DIAMETER``) is centred, for the distance sensors."""

    # V2's distance sensors: 7 per robot, mounted at (x, y) in the body frame and pointing at the angle in row 3
    DISTANCE_SENSOR_ERROR = 0.03
    DISTANCE_SENSOR_DROPOUT_PROB = 0.035
    DISTANCE_SENSOR_OUTLIER_PROB = 0.014
    DISTANCE_SENSOR_RANGE = 1.2
    DISTANCE_SENSORS_ORIENTATION = np.array(
        [
            [-0.04, 0.0, 0.04, 0.05, 0.04, 0.0, -0.04],
            [0.04, 0.06, 0.05, 0.0, -0.05, -0.06, -0.04],
            [math.pi, math.pi / 2, math.pi / 4, 0.0, -math.pi / 4, -math.pi / 2, -math.pi],
        ]
    )

    # V2's on-board sensor models (encoders, IMU, magnetometer, orientation): values and noise of its simulator
    ENCODER_COUNTS_PER_REVOLUTION = 28
    MOTOR_GEAR_RATIO = 100.37
    IMU_ORIENTATION = np.array([0.0594 - 0.00319, 0.0344628 - 0.0475, 0.0])
    ENCODER_NOISE_STD = 0.25
    ACCELEROMETER_NOISE_STDS = np.array([0.012929, 0.012127, 0.052979])
    GYRO_NOISE_STDS = np.array([0.001663, 0.001216, 0.002372])
    MAGNETOMETER_NOISE_STDS = np.array([3.275843, 2.365798, 5.232685])
    MAGNETOMETER_Z_AVG = -39.8594
    MAGNETOMETER_XY_AVG = 6.0712
    ORIENTATION_NOISE_STD = 0.310830

    MAX_WHEEL_VELOCITY = MAX_LINEAR_VELOCITY / WHEEL_RADIUS
    MAX_ANGULAR_VELOCITY = 2.0 * (WHEEL_RADIUS / ROBOT_DIAMETER) * (MAX_LINEAR_VELOCITY / WHEEL_RADIUS)

    def __init__(
        self,
        *,
        number_of_robots: int = 0,
        show_figure: bool = False,
        initial_conditions: FloatArray = np.array([]),  # noqa: B008 - V2's default, never mutated
        use_distance_sensors: bool = False,
        obstacles: FloatArray | None = None,
        show_obstacles: bool = True,
        show_arena_boundaries: bool = True,
        show_robot_patches: bool = True,
        show_distance_endpoints: bool = True,
        show_distance_rays: bool = False,
    ) -> None:
        if not 0 <= number_of_robots <= 50:
            raise AssertionError('Number of robots must be >= 0 and <= 50')
        n = number_of_robots
        self.number_of_robots = n
        self.show_figure = show_figure
        self.show_obstacles = show_obstacles
        self.show_arena_boundaries = show_arena_boundaries
        self.show_robot_patches = show_robot_patches
        self.show_distance_endpoints = show_distance_endpoints
        self.show_distance_rays = show_distance_rays
        self._velocities = np.zeros((2, n))
        self._velocities_old = np.zeros((2, n))
        self._poses = initial_conditions.astype(float).copy() if initial_conditions.size > 0 else np.zeros((3, n))
        self._distances = np.full((7, n), np.nan)  # NaN until the first sensor simulation, as V2
        self._accelerations = np.zeros((3, n))
        self._orientations = np.zeros(n)
        self._magnetic_fields = np.zeros((3, n))
        self._gyros = np.zeros((3, n))
        self._initial_encoders = np.zeros((2, n))
        self._encoders = np.zeros((2, n))
        self._leds = np.zeros((3, n))
        self._distance_sensors_enabled = use_distance_sensors
        self._distance_endpoints = np.full((2, 7, n), np.nan)
        self.obstacles = obstacles
        self._fig: Any = None
        self._axes_handle: Any = None
        if show_figure:
            self._initialize_visualization()
        self.initializing = True

    # ------------------------------------------------------------------ what a Robotarium must do

    @abstractmethod
    def get_poses(self) -> FloatArray: ...

    @abstractmethod
    def initialize(self, initial_conditions: FloatArray) -> None: ...

    @abstractmethod
    def step(self) -> None: ...

    @abstractmethod
    def debug(self) -> None: ...

    # ------------------------------------------------------------------ commands and readings

    def set_velocities(self, ids: Any, velocities: FloatArray) -> None:
        """Set unicycle commands [v; omega] (2xk) of the robots ``ids``; they act at the next ``step()``."""
        velocities = np.asarray(velocities, dtype=float)
        if velocities.ndim != 2 or velocities.shape[0] != 2:
            msg = f'velocities must be a 2xk array [v; omega]; got shape {velocities.shape}.'
            raise RobotariumError(msg)
        if velocities.shape[1] > self.number_of_robots:
            msg = (
                f'Column count of velocities ({velocities.shape[1]}) must be <= number_of_robots '
                f'({self.number_of_robots})'
            )
            raise AssertionError(msg)
        if not np.all(np.isfinite(velocities)):
            msg = 'velocities must be finite; a NaN or inf command would stop the real robots.'
            raise RobotariumError(msg)
        target = np.arange(self.number_of_robots)[ids]
        if np.size(target) != velocities.shape[1]:
            msg = f'ids select {np.size(target)} robots but velocities has {velocities.shape[1]} columns.'
            raise RobotariumError(msg)
        self._velocities[:, target] = velocities

    def robot_colormap(self) -> Any:
        """The colour map V2 colours robots' sensor readings with (matplotlib's tab20)."""
        import matplotlib.pyplot as plt

        return plt.get_cmap('tab20')

    def get_distances(self) -> FloatArray:
        """Seven distance readings per robot (7xN), m; NaN without distance sensors or before the first step."""
        distances: FloatArray = self._distances.copy()
        return distances

    def get_distance_endpoints(self) -> FloatArray:
        """Where each distance reading ends in the world (2 x 7 x N); NaN where nothing was detected."""
        endpoints: FloatArray = self._distance_endpoints.copy()
        return endpoints

    def get_accelerations(self) -> FloatArray:
        accelerations: FloatArray = self._accelerations.copy()
        return accelerations

    def get_orientations(self) -> FloatArray:
        orientations: FloatArray = self._orientations.copy()
        return orientations

    def get_magnetic_fields(self) -> FloatArray:
        fields: FloatArray = self._magnetic_fields.copy()
        return fields

    def get_gyros(self) -> FloatArray:
        gyros: FloatArray = self._gyros.copy()
        return gyros

    def get_encoders(self) -> NDArray[np.int32]:
        """Encoder counts since the start (2xN), as int32."""
        return self._encoders.astype(np.int32) - self._initial_encoders.astype(np.int32)

    # ------------------------------------------------------------------ actuators and verifier

    def _uni_to_diff(self, dxu: FloatArray) -> FloatArray:
        """Wheel speeds (2v -/+ L omega) / (2 r), rad/s, 2xN."""
        r, length = self.WHEEL_RADIUS, self.BASE_LENGTH
        return (1 / (2 * r)) * np.vstack([2 * dxu[0] - length * dxu[1], 2 * dxu[0] + length * dxu[1]])

    def _diff_to_uni(self, dxdd: FloatArray) -> FloatArray:
        r, length = self.WHEEL_RADIUS, self.BASE_LENGTH
        return np.vstack([r / 2 * (dxdd[0] + dxdd[1]), r / length * (dxdd[1] - dxdd[0])])

    def _threshold(self, dxu: FloatArray) -> FloatArray:
        """Clip each wheel to the limit independently (the testbed's actuator model; changes omega / v)."""
        return self._diff_to_uni(np.clip(self._uni_to_diff(dxu), -self.MAX_WHEEL_VELOCITY, self.MAX_WHEEL_VELOCITY))

    def _validate(self, errors: dict[str, int]) -> dict[str, int]:
        """Add this step's counts to ``errors``, as V2's verifier counts them (nothing while initializing).

        A step with any robot outside the arena counts once; every pair of robots whose centres, shifted
        ``COLLISION_OFFSET`` forward, are at most ``COLLISION_DIAMETER`` apart counts once; a step with any wheel
        command over the limit counts once.
        """
        if self.initializing:
            return errors
        p = self._poses
        xmin, xmax, ymin, ymax = ARENA
        if ((p[0] < xmin) | (p[0] > xmax) | (p[1] < ymin) | (p[1] > ymax)).any():
            errors['robots_outside_boundaries'] = errors.get('robots_outside_boundaries', 0) + 1
        if self.number_of_robots > 1:
            shifted = p[:2] + self.COLLISION_OFFSET * np.vstack([np.cos(p[2]), np.sin(p[2])])
            i, j = np.triu_indices(self.number_of_robots, k=1)
            close = int((np.hypot(*(shifted[:, i] - shifted[:, j])) <= self.COLLISION_DIAMETER).sum())
            if close:
                errors['robots_too_close'] = errors.get('robots_too_close', 0) + close
        if (np.abs(self._uni_to_diff(self._velocities)) > self.MAX_WHEEL_VELOCITY).any():
            errors['exceeded_actuator_limits'] = errors.get('exceeded_actuator_limits', 0) + 1
        return errors

    # ------------------------------------------------------------------ drawing (matplotlib, imported when asked)

    def _initialize_visualization(self) -> None:
        """The arena, the robots and the obstacles in a figure of the arena's proportions."""
        import matplotlib.pyplot as plt
        from matplotlib.lines import Line2D
        from matplotlib.patches import Rectangle

        pad = 0.05
        xmin, xmax, ymin, ymax = self.BOUNDARIES
        self._fig, self._axes_handle = plt.subplots(
            figsize=(2.5 * (xmax - xmin + 2 * pad), 2.5 * (ymax - ymin + 2 * pad))
        )
        ax = self._axes_handle
        ax.set_aspect('equal')
        ax.set_xlim(xmin - pad, xmax + pad)
        ax.set_ylim(ymin - pad, ymax + pad)
        ax.axis('off')
        if self.show_arena_boundaries:
            ax.add_patch(
                Rectangle((xmin, ymin), xmax - xmin, ymax - ymin, linewidth=2, edgecolor='k', facecolor='none')
            )
        self._robot_handle = None
        if self.show_robot_patches:
            self._robot_handle = ax.scatter(
                self._poses[0], self._poses[1], s=60, color='gold', edgecolors='k', zorder=2
            )
        colours = [self.robot_colormap()(i % 20) for i in range(self.number_of_robots) for _ in range(7)]
        if self._distance_sensors_enabled and self.show_distance_endpoints:
            self._endpoint_handle = ax.scatter(
                np.full(len(colours), np.nan), np.full(len(colours), np.nan), s=50, c=colours, zorder=3
            )
        if self._distance_sensors_enabled and self.show_distance_rays:
            from matplotlib.collections import LineCollection

            self._ray_handle = ax.add_collection(LineCollection([], linewidths=0.5, colors=colours, zorder=2))
        if self.show_obstacles and self.obstacles is not None:
            for segment in np.asarray(self.obstacles, dtype=float):
                ax.add_line(Line2D(segment[:, 0], segment[:, 1], linewidth=4, color='0.5'))
        plt.ion()
        plt.show()
        plt.subplots_adjust(left=0.01, right=0.99, bottom=0.01, top=0.99)

    def _calculate_endpoints(self, distances: FloatArray) -> FloatArray:
        """World points (2 x 7 x N) where the readings ``distances`` end; NaN where a sensor saw nothing.

        As V2, the rays start at the sensors' mounts on the axle frame (the readings themselves are simulated from
        the body centre ``CENTER_OFFSET`` ahead).
        """
        mounts = self.DISTANCE_SENSORS_ORIENTATION
        c, s = np.cos(self._poses[2]), np.sin(self._poses[2])
        x = c * mounts[0][:, None] - s * mounts[1][:, None] + self._poses[0]
        y = s * mounts[0][:, None] + c * mounts[1][:, None] + self._poses[1]
        angle = self._poses[2][None, :] + mounts[2][:, None]
        seen = np.where(distances >= 0, distances, np.nan)
        return np.stack([x + seen * np.cos(angle), y + seen * np.sin(angle)])

    def _draw_distances(self) -> None:
        """The readings' endpoints (one colour per robot) and, if asked, the rays from the mounts."""
        ends = self._distance_endpoints
        if self.show_distance_endpoints:
            self._endpoint_handle.set_offsets(np.column_stack([ends[0].T.ravel(), ends[1].T.ravel()]))
        if self.show_distance_rays:
            mounts = self.DISTANCE_SENSORS_ORIENTATION
            c, s = np.cos(self._poses[2]), np.sin(self._poses[2])
            x = c * mounts[0][:, None] - s * mounts[1][:, None] + self._poses[0]
            y = s * mounts[0][:, None] + c * mounts[1][:, None] + self._poses[1]
            segments = np.stack([np.stack([x, y], axis=-1), np.stack([ends[0], ends[1]], axis=-1)], axis=2)
            self._ray_handle.set_segments(segments.transpose(1, 0, 2, 3).reshape(-1, 2, 2))

    def _draw_robots(self) -> None:
        if self._robot_handle is not None:
            self._robot_handle.set_offsets(self._poses[:2].T)
        self._fig.canvas.draw_idle()
        self._fig.canvas.flush_events()
