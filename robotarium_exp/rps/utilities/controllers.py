"""``rps.utilities.controllers``: the position and pose controllers the initialization and user scripts use.

V2's names and keyword defaults. The pose controllers: the CLF law of Aicardi et al. (the error rotated into the
goal's frame, approach angle alpha, heading law k alpha + gamma cos(alpha) sinc(alpha) (alpha + h theta)), with
wheel-limit scaling; the hybrid law (approach with the heading law, then turn in place); and their *parking*
wrappers, which hold a robot still once it is at its pose.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.rps.utilities.columns import multiply_each, robot_columns, robot_values
from robotarium_exp.rps.utilities.transformations import (
    create_si_to_uni_dynamics,
    create_si_to_uni_dynamics_with_backwards_motion,
    create_si_to_uni_mapping,
    create_uni_to_si_mapping,
)

__all__ = [  # V2's module also hands out the transformations to ``from rps.utilities.controllers import *``
    'create_pose_controller_clf',
    'create_pose_controller_hybrid',
    'create_pose_parking_controller_clf',
    'create_pose_parking_controller_hybrid',
    'create_si_position_controller',
    'create_si_to_uni_dynamics',
    'create_si_to_uni_dynamics_with_backwards_motion',
    'create_si_to_uni_mapping',
    'create_uni_position_controller',
    'create_uni_to_si_mapping',
    'np',
]

FloatArray = NDArray[np.float64]


def create_si_position_controller(
    x_velocity_gain: float = 0.8, y_velocity_gain: float = 0.8, velocity_magnitude_limit: float = 0.15
) -> Callable[[FloatArray, FloatArray], FloatArray]:
    """``f(x, goals) -> dxi``: proportional single-integrator control, norm-clamped."""
    for name, gain in (('x_velocity_gain', x_velocity_gain), ('y_velocity_gain', y_velocity_gain)):
        if not (isinstance(gain, (int, float)) and gain > 0):
            raise AssertionError(f'{name} must be a positive number.')
    if not (isinstance(velocity_magnitude_limit, (int, float)) and velocity_magnitude_limit >= 0):
        raise AssertionError('velocity_magnitude_limit must be non-negative.')
    return si_position_law(x_velocity_gain, y_velocity_gain, velocity_magnitude_limit, mixed=True)


def si_position_law(
    x_velocity_gain: float, y_velocity_gain: float, velocity_magnitude_limit: float, *, mixed: bool
) -> Callable[[FloatArray, FloatArray], FloatArray]:
    """``f(x, goals) -> dxi``: the gains times the position error, scaled down to ``velocity_magnitude_limit``.

    ``mixed``: V2's product ``diag(gains) @ error``, where a NaN or inf in one coordinate of a robot's error reaches
    both of its commands (0 * NaN is NaN); else classic's, coordinate by coordinate. Equal on finite input."""
    gains = np.diag([x_velocity_gain, y_velocity_gain])

    def controller(x: FloatArray, goals: FloatArray) -> FloatArray:
        _check_shapes(x, goals, 2, 2)
        error = goals - x
        dxi = gains @ error if mixed else np.vstack([x_velocity_gain * error[0], y_velocity_gain * error[1]])
        norms = np.linalg.norm(dxi, axis=0)  # as both officials (NaN where hypot says inf: no clamp then)
        over = norms > velocity_magnitude_limit
        dxi[:, over] = velocity_magnitude_limit * dxi[:, over] / norms[over]
        return dxi

    return controller


def create_pose_controller_hybrid(
    linear_velocity_gain: float = 0.8,
    angular_velocity_limit: float = np.pi,
    velocity_magnitude_limit: float = 0.15,
    position_error: float = 0.03,
    position_epsilon: float = 0.01,
    rotation_error: float = 0.05,
) -> Callable[..., Any]:
    """``f(states, poses[, in_approach_state]) -> dxu`` (or ``(dxu, approach_state)``): V2's two-phase law.

    Per robot, while in the approach phase and farther than ``position_error - position_epsilon``: drive to the
    position with the heading law (`create_si_to_uni_dynamics` with ``linear_velocity_gain``) on the
    position error clamped to ``velocity_magnitude_limit`` (so at most 0.8 x 0.15 = 0.12 m/s by default).
    Otherwise, while the heading is off by more than ``rotation_error``: turn in place at twice the heading error,
    and stay out of the approach phase unless farther than ``position_error``. Otherwise: stop.

    The phases are remembered between calls, one per robot, and restart (all approaching) whenever the number of
    robots in a call changes, as V2's; pass ``in_approach_state`` (N values, 1 approaching, 0 not; updated in
    place) to keep them yourself, and the phases are returned with the commands.
    """
    heading_law = create_si_to_uni_dynamics(linear_velocity_gain, angular_velocity_limit)
    remembered = {'approach_state': np.ones(0)}

    def controller(states: FloatArray, poses: FloatArray, in_approach_state: FloatArray | None = None) -> Any:
        n = states.shape[1]
        if in_approach_state is not None:
            approach_state = in_approach_state
        else:
            if remembered['approach_state'].shape[0] != n:
                remembered['approach_state'] = np.ones(n)
            approach_state = remembered['approach_state']
        goals, headings, flags = (
            robot_columns(poses, n),
            robot_columns(poses, n, row=2),
            robot_values(approach_state, n),
        )
        error = goals - states[:2, :n]
        distance = np.hypot(*error)
        turn = np.arctan2(np.sin(headings - states[2, :n]), np.cos(headings - states[2, :n]))
        approach = flags != 0  # V2 tests each robot's distance only while it approaches
        if approach.any():
            approach &= distance > position_error - position_epsilon
        rotate = np.zeros(n, dtype=bool)
        if (~approach).any():  # V2 tests the heading only of robots not approaching
            rotate[~approach] = np.abs(turn[~approach]) > rotation_error
        for i in np.flatnonzero(rotate):  # V2 writes each phase as 1 or 0 into the caller's list or array
            approach_state[i] = 1 if distance[i] > position_error else 0
        dxu = np.zeros((2, n))
        if approach.any():
            states[:, np.flatnonzero(approach)[0]].reshape(3, 1)  # V2 maps each robot's pose as a 3x1 array
            over = distance[approach] > velocity_magnitude_limit
            scale = np.where(over, velocity_magnitude_limit / np.where(over, distance[approach], 1.0), 1.0)
            dxu[:, approach] = heading_law(error[:, approach] * scale, states[:, :n][:, approach])
        dxu[1, rotate] = 2 * turn[rotate]
        return (dxu, approach_state) if in_approach_state is not None else dxu

    return controller


def _check_shapes(
    states: FloatArray, poses: FloatArray, pose_rows: int, state_rows: int = 3, *, count_first: bool = False
) -> None:
    """V2's checks of a controller's arguments (its messages): states ``state_rows`` x N, goals ``pose_rows`` x N.

    ``count_first``: read N from ``states`` before checking, as V2's CLF controller does (a 1-D ``states`` then
    fails on its missing second dimension, not on its rows)."""
    if count_first:
        states.shape[1]
    if states.shape[0] != state_rows:
        raise AssertionError(f'states must be {state_rows}xN.')
    if poses.shape[0] != pose_rows:
        raise AssertionError(f'poses must be {pose_rows}xN.')
    if poses.shape[1] != states.shape[1]:
        raise AssertionError('states and poses must have the same number of columns.')


def create_uni_position_controller(
    x_velocity_gain: float = 0.8,
    y_velocity_gain: float = 0.8,
    velocity_magnitude_limit: float = 0.15,
    projection_distance: float = 0.03,
) -> Callable[[FloatArray, FloatArray], FloatArray]:
    """``f(states, points) -> dxu``: the single-integrator position controller on the points ``projection_distance``
    ahead of the robots, through the near-identity map."""
    si_controller = create_si_position_controller(x_velocity_gain, y_velocity_gain, velocity_magnitude_limit)
    si_to_uni, uni_to_si_states = create_si_to_uni_mapping(projection_distance=projection_distance)

    def controller(states: FloatArray, poses: FloatArray) -> FloatArray:
        _check_shapes(states, poses, 2)
        return si_to_uni(si_controller(uni_to_si_states(states), poses), states)

    return controller


def create_pose_controller_clf(
    approach_angle_gain: float = 1,
    desired_angle_gain: float = 2.7,
    rotation_error_gain: float = 1,
    wheel_velocity_limit: float = 10.0,
    wheel_radius: float = 0.016,
    base_length: float = 0.105,
) -> Callable[[FloatArray, FloatArray], FloatArray]:
    """``f(states, poses) -> dxu``: the CLF pose controller, each robot's command scaled to the wheel limit."""
    gamma, k, h = approach_angle_gain, desired_angle_gain, rotation_error_gain
    wheel_map = np.linalg.inv(  # V2 inverts the wheel map when it creates the controller: its errors then
        np.array([[wheel_radius / 2, wheel_radius / 2], [-wheel_radius / base_length, wheel_radius / base_length]])
    )

    def controller(states: FloatArray, poses: FloatArray) -> FloatArray:
        _check_shapes(states, poses, 3, count_first=True)
        return clf_commands(states, poses, (gamma, k, h), wheel_map, wheel_velocity_limit)

    return controller


def clf_commands(
    states: FloatArray, poses: FloatArray, gains: tuple[Any, Any, Any], wheel_map: FloatArray, wheel_limit: float
) -> FloatArray:
    """The CLF pose law's commands for poses ``states`` (3 x N) and goals ``poses``: ``gains`` = (approach angle,
    desired angle, rotation error), each robot's command scaled to ``wheel_limit`` through ``wheel_map`` ([v; omega]
    to wheel speeds)."""
    gamma, k, h = gains
    if states.shape[1] > 0:
        multiply_each(gamma, k, h)  # V2's loop multiplies each gain with a float64: its errors then
    goal = poses[2]
    dx, dy = poses[0] - states[0], poses[1] - states[1]
    ex = np.cos(goal) * dx + np.sin(goal) * dy  # the position error in the goal's frame
    ey = -np.sin(goal) * dx + np.cos(goal) * dy
    e = np.hypot(ex, ey)
    theta = np.arctan2(ey, ex)
    alpha = np.angle(np.exp(1j * (theta - (states[2] - goal))))
    sinc = np.where(np.abs(alpha) < 1e-6, 1.0, np.sin(alpha) / np.where(alpha == 0, 1.0, alpha))
    v = gamma * e * np.cos(alpha)
    omega = k * alpha + gamma * np.cos(alpha) * sinc * (alpha + h * theta)
    wheels = np.abs(wheel_map @ np.vstack([v, omega])).max(axis=0)
    scale = np.where(wheels > wheel_limit, wheel_limit / np.maximum(wheels, 1e-300), 1.0)
    return np.vstack([v, omega]) * scale


def _parking(
    controller: Callable[[FloatArray, FloatArray], FloatArray], position_error: float, rotation_error: float
) -> Callable[[FloatArray, FloatArray], FloatArray]:
    """``controller`` with the commands of robots already at their pose set to zero."""

    def parked(states: FloatArray, poses: FloatArray) -> FloatArray:
        dxu = controller(states, poses)
        near = np.hypot(*(states[:2] - poses[:2])) < position_error
        aligned = np.abs(np.angle(np.exp(1j * (states[2] - poses[2])))) < rotation_error
        dxu[:, near & aligned] = 0.0
        return dxu

    return parked


def create_pose_parking_controller_clf(
    approach_angle_gain: float = 1,
    desired_angle_gain: float = 2.7,
    rotation_error_gain: float = 1,
    wheel_velocity_limit: float = 10.0,
    wheel_radius: float = 0.016,
    base_length: float = 0.105,
    position_error: float = 0.05,
    rotation_error: float = 0.2,
) -> Callable[[FloatArray, FloatArray], FloatArray]:
    """The CLF pose controller that holds a robot still once it is within the errors of its pose."""
    clf = create_pose_controller_clf(
        approach_angle_gain, desired_angle_gain, rotation_error_gain, wheel_velocity_limit, wheel_radius, base_length
    )
    return _parking(clf, position_error, rotation_error)


def create_pose_parking_controller_hybrid(
    linear_velocity_gain: float = 0.8,
    angular_velocity_limit: float = np.pi,
    velocity_magnitude_limit: float = 0.15,
    position_error: float = 0.05,
    position_epsilon: float = 0.01,
    rotation_error: float = 0.2,
) -> Callable[[FloatArray, FloatArray], FloatArray]:
    """The hybrid pose controller that holds a robot still once it is within the errors of its pose."""
    hybrid = create_pose_controller_hybrid(
        linear_velocity_gain,
        angular_velocity_limit,
        velocity_magnitude_limit,
        position_error,
        position_epsilon,
        rotation_error,
    )
    return _parking(hybrid, position_error, rotation_error)
