"""Classic ``rps.utilities.controllers``: position and pose controllers, classic names, defaults and laws.

* ``create_si_position_controller``: V2's proportional law with classic's gains of 1 (V2: 0.8), norm-clamped.
* ``create_clf_unicycle_position_controller``: v = k_v d cos(phi - theta), omega = k_w d sin(phi - theta), with d
  the distance to the goal and phi the bearing of the goal.
* ``create_clf_unicycle_pose_controller``: V2's CLF pose law without V2's wheel-limit scaling. (Classic also prints
  three of its intermediate values for every robot at every call, leftover debugging output not reproduced, and
  returns NaN for a robot exactly on its approach line, where this law takes the limit.)
* ``create_hybrid_unicycle_pose_controller``: drive straight at the goal with the heading law until within
  ``position_error - position_epsilon``, then turn in place until within ``rotation_error``; stateless, as classic
  (its ``input_approach_state`` argument has no effect).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.rps.utilities import controllers as v2
from robotarium_exp.rps_classic.utilities.transformations import create_si_to_uni_dynamics

FloatArray = NDArray[np.float64]
Controller = Callable[[FloatArray, FloatArray], FloatArray]


def create_si_position_controller(
    x_velocity_gain: float = 1, y_velocity_gain: float = 1, velocity_magnitude_limit: float = 0.15
) -> Controller:
    """``f(xi, positions) -> dxi``: gains times the position error, scaled down to ``velocity_magnitude_limit``."""
    return v2.create_si_position_controller(x_velocity_gain, y_velocity_gain, velocity_magnitude_limit)


def create_clf_unicycle_position_controller(
    linear_velocity_gain: float = 0.8, angular_velocity_gain: float = 3
) -> Controller:
    """``f(states, positions) -> dxu``: the CLF position law, unclamped (the simulator clips v and omega)."""

    def position_uni_clf_controller(states: FloatArray, positions: FloatArray) -> FloatArray:
        error = positions[:2] - states[:2]
        distance = np.hypot(error[0], error[1])
        off_heading = np.arctan2(error[1], error[0]) - states[2]
        return np.vstack(
            [
                linear_velocity_gain * distance * np.cos(off_heading),
                angular_velocity_gain * distance * np.sin(off_heading),
            ]
        )

    return position_uni_clf_controller


def create_clf_unicycle_pose_controller(
    approach_angle_gain: float = 1, desired_angle_gain: float = 2.7, rotation_error_gain: float = 1
) -> Controller:
    """``f(states, poses) -> dxu``: the CLF pose law (Aicardi et al.), without a wheel limit."""
    return v2.create_pose_controller_clf(
        approach_angle_gain, desired_angle_gain, rotation_error_gain, wheel_velocity_limit=np.inf
    )


def create_hybrid_unicycle_pose_controller(
    linear_velocity_gain: float = 1,
    angular_velocity_gain: float = 2,
    velocity_magnitude_limit: float = 0.15,
    angular_velocity_limit: float = np.pi,
    position_error: float = 0.05,
    position_epsilon: float = 0.02,
    rotation_error: float = 0.05,
) -> Callable[..., FloatArray]:
    """``f(states, poses) -> dxu``: approach, then turn in place, then stop (see the module docstring).

    Approaching: the position error, scaled down to ``velocity_magnitude_limit``, through the heading law with
    ``linear_velocity_gain`` and ``angular_velocity_limit``. Turning: omega = ``angular_velocity_gain`` times the
    wrapped heading error.
    """
    heading_law = create_si_to_uni_dynamics(linear_velocity_gain, angular_velocity_limit)

    def pose_uni_hybrid_controller(
        states: FloatArray,
        poses: FloatArray,
        input_approach_state: NDArray[np.float64] | None = None,  # classic's, without effect
    ) -> FloatArray:
        error = poses[:2] - states[:2]
        distance = np.hypot(error[0], error[1])
        scale = np.minimum(1.0, velocity_magnitude_limit / np.maximum(distance, 1e-300))
        turn = np.arctan2(np.sin(poses[2] - states[2]), np.cos(poses[2] - states[2]))
        approaching = distance > position_error - position_epsilon
        turning = ~approaching & (np.abs(turn) > rotation_error)
        dxu = np.zeros((2, states.shape[1]))
        dxu[:, approaching] = heading_law(error[:, approaching] * scale[approaching], states[:, approaching])
        dxu[1, turning] = angular_velocity_gain * turn[turning]
        return dxu

    return pose_uni_hybrid_controller
