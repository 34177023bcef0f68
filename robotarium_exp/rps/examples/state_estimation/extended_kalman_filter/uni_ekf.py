"""``UnicycleEKF``: an extended Kalman filter for a unicycle, with V2's interface (``uni_ekf``).

State ``[x, y, theta]``. Prediction from wheel-encoder speeds (v, omega) with the forward-Euler unicycle model; the
encoder noise ``M`` (covariance of the right and left wheel speeds, rad^2/s^2) enters through the wheels' Jacobian,
the process noise as ``Q dt``. Updates: position (GPS), range and bearing to a beacon, heading, yaw rate. Every
covariance update uses the Joseph form, which keeps ``P`` symmetric positive semi-definite.

Where V2's helper differs, on purpose: ``update_brearing`` (V2's spelling, kept) uses the bearing's true Jacobian
(V2 uses the beacon's position as the measurement row); ``update_gyro`` integrates over the ``dt`` it is given (V2
measures wall-clock time and ignores the argument); ``update_orientation`` prints nothing.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def wrap_angle(angle: Any) -> Any:
    """``angle`` wrapped to [-pi, pi]."""
    return np.arctan2(np.sin(angle), np.cos(angle))


class UnicycleEKF:
    """EKF of a unicycle robot's pose; ``state`` (3,) and ``P`` (3x3) are the estimate and its covariance.

    Parameters
    ----------
    initial_state, initial_covariance
        Prior ``[x, y, theta]`` and its 3x3 covariance.
    b, r
        Wheel base (the whole axle length) and wheel radius, m.
    M
        2x2 covariance of the wheel-speed measurements [right, left], (rad/s)^2.
    Q
        3x3 process-noise covariance rate (multiplied by ``dt`` per prediction).
    """

    def __init__(
        self,
        initial_state: np.ndarray,
        initial_covariance: np.ndarray,
        b: float,
        r: float,
        M: np.ndarray,
        Q: np.ndarray,
    ) -> None:
        self.state = np.asarray(initial_state, dtype=float).reshape(3).copy()
        self.covariance = np.asarray(initial_covariance, dtype=float)
        self.P = self.covariance
        self.base_length = b
        self.wheel_radius = r
        self.wheel_encoder_noise_covariance_matrix = np.asarray(M, dtype=float)
        self.Q = np.asarray(Q, dtype=float)
        self.previous_theta = self.state[2]

    # ------------------------------------------------------------------ model

    def form_fx(self, v: float, w: float, dt: float) -> FloatArray:
        """The state increment of one step (3x1)."""
        theta = self.state[2]
        return np.array([[dt * v * np.cos(theta)], [dt * v * np.sin(theta)], [dt * w]])

    def form_F(self, v: float, dt: float) -> FloatArray:
        """Jacobian of the step with respect to the state."""
        theta = self.state[2]
        return np.array([[1.0, 0.0, -v * dt * np.sin(theta)], [0.0, 1.0, v * dt * np.cos(theta)], [0.0, 0.0, 1.0]])

    def form_G(self, dt: float) -> FloatArray:
        """Jacobian of the step with respect to (v, omega): the state moves by ``G @ [v, omega]``."""
        theta = self.state[2]
        return np.array([[np.cos(theta) * dt, 0.0], [np.sin(theta) * dt, 0.0], [0.0, dt]])

    def form_Q(self, dt: float) -> FloatArray:
        return self.Q * dt

    def form_wheel_encoder_process_noise_matrix(self, dt: float) -> FloatArray:
        """``L M L^T`` with ``L`` the step's Jacobian with respect to the [right, left] wheel speeds."""
        theta = self.state[2]
        along = self.wheel_radius / 2 * dt
        turn = self.wheel_radius / self.base_length * dt
        jacobian = np.array(
            [[along * np.cos(theta)] * 2, [along * np.sin(theta)] * 2, [turn, -turn]],
        )
        covariance: FloatArray = jacobian @ self.wheel_encoder_noise_covariance_matrix @ jacobian.T
        return covariance

    def predict(self, v: float, w: float, dt: float) -> None:
        """Propagate the estimate by one step of (v, omega) over ``dt``."""
        jacobian = self.form_F(v, dt)
        noise = self.form_wheel_encoder_process_noise_matrix(dt) + self.form_Q(dt)
        self.P = jacobian @ self.P @ jacobian.T + noise
        self.state = self.state + self.form_G(dt) @ np.array([v, w], dtype=float)
        self.state[2] = wrap_angle(self.state[2])

    # ------------------------------------------------------------------ measurements

    def _correct(self, row: FloatArray, innovation: FloatArray, noise: FloatArray) -> None:
        """The Kalman correction for measurement Jacobian ``row`` (m x 3), Joseph form."""
        gain = self.P @ row.T @ np.linalg.inv(row @ self.P @ row.T + noise)
        keep = np.eye(3) - gain @ row
        self.P = keep @ self.P @ keep.T + gain @ noise @ gain.T
        self.state = self.state + gain @ innovation
        self.state[2] = wrap_angle(self.state[2])

    def update_gps(self, gps_measurement: np.ndarray, R_gps: np.ndarray) -> None:
        """Correct with a measured position (x, y) of the axle centre; ``R_gps`` its 2x2 covariance."""
        row = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
        measured = np.asarray(gps_measurement, dtype=float).reshape(2)
        self._correct(row, measured - self.state[:2], np.atleast_2d(np.asarray(R_gps, dtype=float)))

    def update_range(self, beacon_position: np.ndarray, range_measurement: float, R_range: float) -> None:
        """Correct with a measured distance to a beacon at (bx, by); ``R_range`` its variance (m^2)."""
        beacon = np.asarray(beacon_position, dtype=float).reshape(-1)[:2]
        dx, dy = beacon - self.state[:2]
        rho = max(float(np.hypot(dx, dy)), 1e-6)
        row = np.array([[-dx / rho, -dy / rho, 0.0]])
        noise = np.array([[float(np.asarray(R_range).reshape(-1)[0])]])
        self._correct(row, np.array([float(range_measurement) - rho]), noise)

    def update_brearing(
        self,
        beacon_position: np.ndarray,
        bearing_measurement: float,
        R_bearing: np.ndarray | None = None,
    ) -> None:
        """Correct with the bearing of a beacon in the robot's frame, rad; ``R_bearing`` its variance."""
        beacon = np.asarray(beacon_position, dtype=float).reshape(-1)[:2]
        dx, dy = beacon - self.state[:2]
        rho2 = max(dx * dx + dy * dy, 1e-12)
        row = np.array([[dy / rho2, -dx / rho2, -1.0]])
        expected = np.arctan2(dy, dx) - self.state[2]
        noise = np.atleast_2d(np.asarray(0.0 if R_bearing is None else R_bearing, dtype=float))
        self._correct(row, np.array([wrap_angle(float(bearing_measurement) - expected)]), noise)

    def update_orientation(self, orientation: float, R_orientation: float | None = None) -> None:
        """Correct with a measured heading, rad; ``R_orientation`` its variance."""
        row = np.array([[0.0, 0.0, 1.0]])
        noise = np.atleast_2d(np.asarray(0.0 if R_orientation is None else R_orientation, dtype=float))
        innovation = wrap_angle(wrap_angle(float(np.asarray(orientation).reshape(-1)[0])) - self.state[2])
        self._correct(row, np.array([innovation]), noise)

    def update_gyro(self, yaw_rate: float, dt: float, R_gyro: np.ndarray | None = None) -> None:
        """Correct the heading change since the last gyro update with ``yaw_rate * dt``; ``R_gyro`` its variance."""
        row = np.array([[0.0, 0.0, 1.0]])
        turned = wrap_angle(self.state[2] - self.previous_theta)
        innovation = wrap_angle(float(np.asarray(yaw_rate).reshape(-1)[0]) * dt - turned)
        noise = np.atleast_2d(np.asarray(0.0 if R_gyro is None else R_gyro, dtype=float))
        self._correct(row, np.array([innovation]), noise)
        self.previous_theta = self.state[2]
