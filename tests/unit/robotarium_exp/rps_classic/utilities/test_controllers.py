"""Classic controllers, checked against hand computations robot by robot on random states."""

from __future__ import annotations

import numpy as np
import pytest

import robotarium_exp.rps.utilities.controllers as v2_controllers
import robotarium_exp.rps_classic.utilities.controllers as classic_controllers


def test_si_position_controller_gain_one_not_v2s_point_eight(states) -> None:
    x, goals = states
    goals = x[:2] + 0.05 * (goals[:2] - x[:2])  # small errors: below the magnitude limit
    np.testing.assert_allclose(
        classic_controllers.create_si_position_controller()(x[:2], goals), goals - x[:2], atol=1e-15
    )
    np.testing.assert_allclose(
        v2_controllers.create_si_position_controller()(x[:2], goals), 0.8 * (goals - x[:2]), atol=1e-15
    )
    far = classic_controllers.create_si_position_controller()(x[:2], x[:2] + 10.0)
    np.testing.assert_allclose(np.hypot(*far), 0.15)


def test_clf_unicycle_position_controller_by_hand(states) -> None:
    x, goals = states
    dxu = classic_controllers.create_clf_unicycle_position_controller(
        linear_velocity_gain=0.7, angular_velocity_gain=2.5
    )(x, goals[:2])
    for i in range(x.shape[1]):
        dx, dy = goals[0, i] - x[0, i], goals[1, i] - x[1, i]
        d, bearing = np.hypot(dx, dy), np.arctan2(dy, dx)
        assert dxu[0, i] == pytest.approx(0.7 * d * np.cos(bearing - x[2, i]), abs=1e-14)
        assert dxu[1, i] == pytest.approx(2.5 * d * np.sin(bearing - x[2, i]), abs=1e-14)


def test_clf_unicycle_pose_controller_by_hand(states) -> None:
    x, goals = states
    dxu = classic_controllers.create_clf_unicycle_pose_controller()(x, goals)
    for i in range(x.shape[1]):
        c, s = np.cos(goals[2, i]), np.sin(goals[2, i])
        ex, ey = np.array([[c, s], [-s, c]]) @ (goals[:2, i] - x[:2, i])
        theta = np.arctan2(ey, ex)
        alpha = np.angle(np.exp(1j * (theta - x[2, i] + goals[2, i])))
        assert dxu[0, i] == pytest.approx(np.hypot(ex, ey) * np.cos(alpha), abs=1e-14)
        turn = 2.7 * alpha + np.cos(alpha) * np.sin(alpha) / alpha * (alpha + theta)
        assert dxu[1, i] == pytest.approx(turn, abs=1e-12)


def test_hybrid_pose_controller_by_hand(states) -> None:
    x, goals = states
    goals[:2, :3] = x[:2, :3] + 0.01  # three robots close enough to turn (one also aligned: it stops)
    goals[2, 2] = x[2, 2] + 0.01
    dxu = classic_controllers.create_hybrid_unicycle_pose_controller()(x, goals)
    for i in range(x.shape[1]):
        error = goals[:2, i] - x[:2, i]
        d = np.hypot(*error)
        turn = np.angle(np.exp(1j * (goals[2, i] - x[2, i])))
        if d > 0.03:
            u = error * min(1.0, 0.15 / d)
            along = np.cos(x[2, i]) * u[0] + np.sin(x[2, i]) * u[1]
            across = -np.sin(x[2, i]) * u[0] + np.cos(x[2, i]) * u[1]
            expected = [along, np.pi * np.arctan2(across, along) / (np.pi / 2)]
        elif abs(turn) > 0.05:
            expected = [0.0, 2 * turn]
        else:
            expected = [0.0, 0.0]
        np.testing.assert_allclose(dxu[:, i], expected, atol=1e-14)
    assert np.all(dxu[:, 2] == 0) and np.all(dxu[0, :2] == 0)
