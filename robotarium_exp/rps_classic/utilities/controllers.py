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
from robotarium_exp.rps.utilities.columns import multiply_each, robot_columns
from robotarium_exp.rps_classic.utilities.checks import (
    ARRAY,
    AT_LEAST_ZERO,
    NOT_NEGATIVE,
    POSITIVE,
    Checked,
    bound,
    columns,
    enforce,
    pair,
    rows,
    typed,
)
from robotarium_exp.rps_classic.utilities.transformations import create_si_to_uni_dynamics

FloatArray = NDArray[np.float64]
Controller = Callable[[FloatArray, FloatArray], FloatArray]


XG, YG = 'the x linear velocity gain (x_velocity_gain)', 'the y linear velocity gain (y_velocity_gain)'
SI_GAINS = (
    typed('x_velocity_gain', XG),
    typed('y_velocity_gain', YG),
    typed('velocity_magnitude_limit', 'the velocity magnitude limit (y_velocity_gain)', shown='y_velocity_gain'),
    bound('x_velocity_gain', XG, POSITIVE),
    bound('y_velocity_gain', YG, POSITIVE),
    bound('velocity_magnitude_limit', 'the velocity magnitude limit (velocity_magnitude_limit)', NOT_NEGATIVE),
)
GOALS = 'the robot goal points (positions)'
SI_CONTROLLER = (
    typed('xi', 'the single-integrator robot states (xi)', ARRAY),
    typed('positions', GOALS, ARRAY),
    rows('xi', 2, 'the dimension of the single-integrator robot states (xi) must be 2 ([x;y])'),
    rows('positions', 2, f'the dimension of {GOALS} must be 2 ([x_goal;y_goal])'),
    columns(
        'xi',
        'positions',
        f'the number of single-integrator robot states (xi) must be equal to the number of {GOALS[4:]}. Recieved a '
        'single integrator current position input array of size %r x %r and desired position array of size %r x %r.',
    ),
)

LG, AG = 'the linear velocity gain (linear_velocity_gain)', 'the angular velocity gain (angular_velocity_gain)'
CLF_GAINS = (
    typed('linear_velocity_gain', LG),
    typed('angular_velocity_gain', AG),
    bound('linear_velocity_gain', LG, AT_LEAST_ZERO),
    bound('angular_velocity_gain', AG, AT_LEAST_ZERO),
)
CLF_CONTROLLER = (
    typed('states', 'the single-integrator robot states (xi)', ARRAY),
    typed('positions', GOALS, ARRAY),
    rows('states', 3, 'the dimension of the unicycle robot states (states) must be 3 ([x;y;theta])'),
    rows('positions', 2, 'the dimension of the robot goal positions (positions) must be 2 ([x_goal;y_goal])'),
    columns(
        'states',
        'positions',
        'the number of unicycle robot states (states) must be equal to the number of robot goal positions '
        '(positions). Recieved a current robot pose input array (states) of size %r states %r and desired position '
        'array (positions) of size %r states %r.',
    ),
)


def create_si_position_controller(
    x_velocity_gain: float = 1, y_velocity_gain: float = 1, velocity_magnitude_limit: float = 0.15
) -> Controller:
    """``f(xi, positions) -> dxi``: gains times the position error, scaled down to ``velocity_magnitude_limit``."""
    factory = 'create_si_position_controller'
    enforce(f'In the function {factory}', SI_GAINS, locals())
    controller = v2.si_position_law(x_velocity_gain, y_velocity_gain, velocity_magnitude_limit, mixed=False)
    place = f'In the si_position_controller function created by the {factory} function'
    return Checked(controller, pair(place, SI_CONTROLLER, 'xi', 'positions'))


def create_clf_unicycle_position_controller(
    linear_velocity_gain: float = 0.8, angular_velocity_gain: float = 3
) -> Controller:
    """``f(states, positions) -> dxu``: the CLF position law, unclamped (the simulator clips v and omega)."""
    factory = 'create_clf_unicycle_position_controller'
    enforce(f'In the function {factory}', CLF_GAINS, locals())

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

    place = f'In the function created by the {factory} function'
    return Checked(position_uni_clf_controller, pair(place, CLF_CONTROLLER, 'states', 'positions'))


def create_clf_unicycle_pose_controller(
    approach_angle_gain: float = 1, desired_angle_gain: float = 2.7, rotation_error_gain: float = 1
) -> Controller:
    """``f(states, poses) -> dxu``: the CLF pose law (Aicardi et al.), without a wheel limit; classic checks nothing
    and reads each robot's pose and goal in its loop (`robotarium_exp.rps.utilities.columns`)."""
    gains = (approach_angle_gain, desired_angle_gain, rotation_error_gain)

    def pose_uni_clf_controller(states: FloatArray, poses: FloatArray) -> FloatArray:
        goals, poses_now = _read_poses(states, poses)
        return v2.clf_commands(poses_now, goals, gains, np.eye(2), np.inf)

    return pose_uni_clf_controller


def _read_poses(states: FloatArray, poses: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Goals and poses (3 x N, N the columns of ``states``) read as classic's pose controllers read them."""
    n = states.shape[1]
    headings, angles = robot_columns(poses, n, row=2), robot_columns(states, n, row=2)
    return np.vstack([robot_columns(poses, n), headings]), np.vstack([robot_columns(states, n), angles])


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
    wrapped heading error. As classic, a gain or limit is used only by the robots in its phase.
    """
    heading_law = create_si_to_uni_dynamics(linear_velocity_gain, angular_velocity_limit)

    def pose_uni_hybrid_controller(
        states: FloatArray,
        poses: FloatArray,
        input_approach_state: NDArray[np.float64] = np.empty([0, 0]),  # noqa: B008 - classic's, without effect
    ) -> FloatArray:
        n = states.shape[1]
        input_approach_state.shape[1]  # classic compares its width with N: a list or a 1-D array fails here
        goals, poses_now = _read_poses(states, poses)
        error = goals[:2] - poses_now[:2]
        distance = np.hypot(error[0], error[1])
        turn = np.arctan2(np.sin(goals[2] - poses_now[2]), np.cos(goals[2] - poses_now[2]))
        dxu = np.zeros((2, n))
        if n == 0:
            return dxu
        approaching = distance > position_error - position_epsilon
        turning = np.zeros(n, dtype=bool)
        if (~approaching).any():
            turning[~approaching] = np.abs(turn[~approaching]) > rotation_error
        if approaching.any():
            over = distance[approaching] > velocity_magnitude_limit
            scale = np.where(over, velocity_magnitude_limit / np.where(over, distance[approaching], 1.0), 1.0)
            dxu[:, approaching] = heading_law(error[:, approaching] * scale, states[:, :n][:, approaching])
        if turning.any():
            multiply_each(angular_velocity_gain)
            dxu[1, turning] = angular_velocity_gain * turn[turning]
        return dxu

    return pose_uni_hybrid_controller
