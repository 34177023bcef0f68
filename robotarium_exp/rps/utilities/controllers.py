"""``rps.utilities.controllers``: the position and pose controllers the initialization and user scripts use."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.rps.utilities.transformations import create_si_to_uni_dynamics

FloatArray = NDArray[np.float64]


def create_si_position_controller(
    x_velocity_gain: float = 0.8, y_velocity_gain: float = 0.8, velocity_magnitude_limit: float = 0.15
) -> Callable[[FloatArray, FloatArray], FloatArray]:
    """``f(x, goals) -> dxi``: proportional single-integrator control, norm-clamped."""

    def controller(x: FloatArray, goals: FloatArray) -> FloatArray:
        dxi = np.vstack([x_velocity_gain * (goals[0] - x[0]), y_velocity_gain * (goals[1] - x[1])])
        norms = np.hypot(*dxi)
        over = norms > velocity_magnitude_limit
        dxi[:, over] *= velocity_magnitude_limit / norms[over]
        return dxi

    return controller


def create_pose_controller_hybrid(
    linear_velocity_gain: float = 0.8,
    angular_velocity_limit: float = np.pi,
    velocity_magnitude_limit: float = 0.15,
    position_error: float = 0.03,
    position_epsilon: float = 0.01,
    rotation_error: float = 0.05,
) -> Callable[[FloatArray, FloatArray], FloatArray]:
    """``f(states, poses) -> dxu``: approach the position with the heading law, then turn in place.

    A robot switches to turning when within ``position_error`` of its goal and back to approaching when it drifts
    beyond ``position_error + position_epsilon`` (hysteresis kept between calls).
    """
    approach = create_si_position_controller(linear_velocity_gain, linear_velocity_gain, velocity_magnitude_limit)
    heading_law = create_si_to_uni_dynamics(1.0, angular_velocity_limit)
    state: dict[str, NDArray[np.bool_]] = {}

    def controller(states: FloatArray, poses: FloatArray) -> FloatArray:
        n = states.shape[1]
        approaching = state.setdefault('approaching', np.ones(n, dtype=bool))
        distance = np.hypot(*(states[:2] - poses[:2]))
        approaching[distance <= position_error] = False
        approaching[distance > position_error + position_epsilon] = True
        dxu = heading_law(approach(states[:2], poses[:2]), states)
        turn = np.angle(np.exp(1j * (poses[2] - states[2])))
        rotate = np.vstack([np.zeros(n), np.clip(2.0 * turn, -angular_velocity_limit, angular_velocity_limit)])
        rotate[1, np.abs(turn) <= rotation_error] = 0.0
        dxu[1] = np.clip(dxu[1], -angular_velocity_limit, angular_velocity_limit)
        return np.where(approaching, dxu, rotate)

    return controller
