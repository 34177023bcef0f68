"""V2's unicycle EKF helper: the model's and the measurements' Jacobians by finite differences, the Kalman
corrections against the scalar formulas, the covariance kept symmetric positive semi-definite."""

from __future__ import annotations

import numpy as np
import pytest

import robotarium_exp.rps.examples
import robotarium_exp.rps.examples.state_estimation
import robotarium_exp.rps.examples.state_estimation.extended_kalman_filter
from robotarium_exp.rps.examples.state_estimation.extended_kalman_filter.uni_ekf import UnicycleEKF, wrap_angle

B, R = 0.11, 0.016


def ekf(state=(0.2, -0.1, 0.7), p: float = 0.01) -> UnicycleEKF:
    return UnicycleEKF(np.array(state), p * np.eye(3), B, R, 0.04 * np.eye(2), 1e-4 * np.eye(3))


def step(state: np.ndarray, v: float, w: float, dt: float) -> np.ndarray:
    """The forward-Euler unicycle written out."""
    return state + dt * np.array([v * np.cos(state[2]), v * np.sin(state[2]), w])


def test_the_packages_are_v2_s_example_helpers() -> None:
    for package in (
        robotarium_exp.rps.examples,
        robotarium_exp.rps.examples.state_estimation,
        robotarium_exp.rps.examples.state_estimation.extended_kalman_filter,
    ):
        assert package.__name__.startswith('robotarium_exp.rps.examples')


def test_prediction_and_its_jacobians_by_finite_differences() -> None:
    f = ekf()
    v, w, dt, h = 0.1, 0.8, 0.033, 1e-6
    np.testing.assert_allclose(f.form_fx(v, w, dt)[:, 0], step(f.state, v, w, dt) - f.state, atol=1e-15)
    jac = np.column_stack([(step(f.state + h * e, v, w, dt) - step(f.state - h * e, v, w, dt)) / (2 * h)
                           for e in np.eye(3)])  # fmt: skip
    np.testing.assert_allclose(f.form_F(v, dt), jac, atol=1e-9)
    g = np.column_stack([(step(f.state, v + h, w, dt) - step(f.state, v - h, w, dt)) / (2 * h),
                         (step(f.state, v, w + h, dt) - step(f.state, v, w - h, dt)) / (2 * h)])  # fmt: skip
    np.testing.assert_allclose(f.form_G(dt), g, atol=1e-9)
    # the wheels: v = r (right + left) / 2, omega = r (right - left) / b
    wheels = np.array([[R / 2, R / 2], [R / B, -R / B]])
    expected = f.form_G(dt) @ wheels @ (0.04 * np.eye(2)) @ wheels.T @ f.form_G(dt).T
    np.testing.assert_allclose(f.form_wheel_encoder_process_noise_matrix(dt), expected, atol=1e-18)
    before, covariance = f.state.copy(), f.P.copy()
    f.predict(v, w, dt)
    np.testing.assert_allclose(f.state, step(before, v, w, dt), atol=1e-15)
    np.testing.assert_allclose(f.P, jac @ covariance @ jac.T + expected + 1e-4 * dt * np.eye(3), atol=1e-15)


def test_gps_correction_is_the_scalar_kalman_blend() -> None:
    """Independent axes: each position moves by P / (P + R) of the innovation, its variance to P R / (P + R)."""
    f = ekf(p=0.04)
    f.update_gps(np.array([0.5, 0.3]), 0.01 * np.eye(2))
    gain = 0.04 / 0.05
    np.testing.assert_allclose(f.state[:2], [0.2 + gain * 0.3, -0.1 + gain * 0.4])
    np.testing.assert_allclose(np.diag(f.P), [0.04 * 0.01 / 0.05] * 2 + [0.04])
    assert f.state[2] == 0.7


def test_range_bearing_heading_and_gyro_rows_by_finite_differences() -> None:
    beacon, h = np.array([1.0, 0.5]), 1e-6

    def distance(s):
        return np.hypot(*(beacon - s[:2]))

    def bearing(s):
        return np.arctan2(beacon[1] - s[1], beacon[0] - s[0]) - s[2]

    for measure, update in ((distance, 'update_range'), (bearing, 'update_brearing')):
        g = ekf()
        row = np.array([(measure(g.state + h * e) - measure(g.state - h * e)) / (2 * h) for e in np.eye(3)])
        innovation = 0.05
        k = g.P @ row / (row @ g.P @ row + 1e-3)
        expected = g.state + k * innovation
        getattr(g, update)(beacon, measure(g.state) + innovation, 1e-3)
        np.testing.assert_allclose(g.state, expected, atol=1e-8)
    o = ekf()
    o.update_orientation(0.7 + 2 * np.pi + 0.1, 0.01)  # wrapped before the innovation
    assert o.state[2] == pytest.approx(0.7 + 0.1 * 0.01 / 0.02)
    y = ekf()
    y.predict(0.0, 1.0, 0.1)  # turned 0.1 rad
    turned = y.state[2]
    y.update_gyro(1.0, 0.1, 0.01)  # the gyro agrees: nothing to correct
    assert y.state[2] == pytest.approx(turned) and y.previous_theta == y.state[2]


def test_the_covariance_stays_symmetric_positive_semidefinite_over_random_updates() -> None:
    rng = np.random.default_rng(0)
    f = ekf()
    for _ in range(50):
        f.predict(rng.uniform(-0.2, 0.2), rng.uniform(-2, 2), 0.033)
        f.update_gps(f.state[:2] + rng.normal(0, 0.01, 2), 1e-4 * np.eye(2))
        f.update_brearing(rng.uniform(-1, 1, 2) + 2.0, rng.uniform(-np.pi, np.pi), 0.05)
        f.update_orientation(rng.uniform(-np.pi, np.pi), 0.1)
        np.testing.assert_allclose(f.P, f.P.T, atol=1e-12)
        assert np.linalg.eigvalsh(f.P).min() >= -1e-12 and -np.pi <= f.state[2] <= np.pi
    assert wrap_angle(3 * np.pi / 2) == pytest.approx(-np.pi / 2)
