"""Classic ``rps.utilities.transformations``: single integrator <-> unicycle maps, classic names and defaults.

Three differences from V2 (`robotarium_exp.rps.utilities.transformations`), all classic's:

* ``create_si_to_uni_dynamics``: the turn rate is the angle of the command seen with the *scaled* forward part,
  atan2(across, k along), so the linear gain k also changes omega (V2: atan2(across, along));
* ``create_si_to_uni_mapping`` clips omega to +/- ``angular_velocity_limit`` (default pi); V2 does not clip;
* ``create_si_to_uni_dynamics_with_backwards_motion`` never drives backwards: classic's function of that name
  computes exactly the forward heading law (V2's reverses when the command points behind the robot).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from robotarium_exp.rps.utilities.transformations import FloatArray, Map
from robotarium_exp.rps_classic.utilities.checks import (
    ARRAY,
    NOT_NEGATIVE,
    POSITIVE,
    Check,
    Checked,
    bound,
    columns,
    enforce,
    pair,
    rows,
    typed,
)
from unicycle_mapping import si_to_uni, uni_to_si, uni_to_si_states

__all__ = [
    'create_si_to_uni_dynamics',
    'create_si_to_uni_dynamics_with_backwards_motion',
    'create_si_to_uni_mapping',
    'create_uni_to_si_dynamics',
]


GAINS = (
    typed('linear_velocity_gain', 'the linear velocity gain (linear_velocity_gain)'),
    typed('angular_velocity_limit', 'the angular velocity limit (angular_velocity_limit)'),
    bound('linear_velocity_gain', 'the linear velocity gain (linear_velocity_gain)', POSITIVE),
    bound('angular_velocity_limit', 'the angular velocity limit (angular_velocity_limit)', NOT_NEGATIVE),
)
"""The checks of both heading-law factories (under one name, ``create_si_to_uni_dynamics``, as classic)."""

PROJECTION = 'the projection distance of the new control point (projection_distance)'
MAPPING = (
    typed('projection_distance', PROJECTION),
    typed('angular_velocity_limit', 'the maximum angular velocity command (angular_velocity_limit)'),
    bound('projection_distance', PROJECTION, POSITIVE),
)
"""The checks of ``create_si_to_uni_mapping`` (classic's fourth one tests the projection distance again, so it
never fails: a negative limit passes, as in classic)."""

UNI_TO_SI = (typed('projection_distance', PROJECTION), bound('projection_distance', PROJECTION, POSITIVE))

POSES = (
    typed('poses', 'the current robot poses (poses)', ARRAY),
    rows('poses', 3, 'the dimension of the current pose of each robot must be 3 ([x;y;theta])'),
)


def _commands(name: str, what: str, layout: str, plural: str) -> tuple[Check, ...]:
    """The checks of a created map of ``name`` (2xN commands) and ``poses`` (3xN), in classic's order."""
    return (
        typed(name, f'the {what} ({name})', ARRAY),
        POSES[0],
        rows(name, 2, f'the dimension of the {what} ({name}) must be 2 ({layout})'),
        POSES[1],
        columns(
            name,
            'poses',
            f'the number of {plural} must be equal to the number of current robot poses. Recieved a {plural[:-1]} '
            'array of size %r x %r and current pose array of size %r x %r.',
        ),
    )


SI_COMMANDS = _commands(
    'dxi', 'single integrator velocity inputs', '[x_dot;y_dot]', 'single integrator velocity inputs'
)
UNI_COMMANDS = _commands('dxu', 'unicycle velocity inputs', '[v;w]', 'unicycle velocity inputs')


def _created(map_name: str, factory: str, checks: tuple[Check, ...], first: str, function: Map) -> Map:
    """``function`` behind classic's checks of the map ``map_name`` that ``factory`` creates."""
    place = f'In the {map_name} function created by the {factory} function'
    return Checked(function, pair(place, checks, first, 'poses'))


def create_si_to_uni_dynamics(linear_velocity_gain: float = 1, angular_velocity_limit: float = np.pi) -> Map:
    """The heading law (not a diffeomorphism): v = k (h . u), omega = w_lim atan2(h_perp . u, v) / (pi / 2), with h
    the robot's heading and h_perp its left normal; |omega| stays below 2 w_lim."""
    return _heading_law(linear_velocity_gain, angular_velocity_limit, 'create_si_to_uni_dynamics')


def create_si_to_uni_dynamics_with_backwards_motion(
    linear_velocity_gain: float = 1, angular_velocity_limit: float = np.pi
) -> Map:
    """Classic: the forward heading law of `create_si_to_uni_dynamics`, unchanged (no backwards motion)."""
    factory = 'create_si_to_uni_dynamics_with_backwards_motion'
    return _heading_law(linear_velocity_gain, angular_velocity_limit, factory)


def _heading_law(linear_velocity_gain: float, angular_velocity_limit: float, factory: str) -> Map:
    enforce('In the function create_si_to_uni_dynamics', GAINS, locals())

    def si_to_uni_dyn(dxi: FloatArray, poses: FloatArray) -> FloatArray:
        c, s = np.cos(poses[2, :]), np.sin(poses[2, :])
        v = linear_velocity_gain * (c * dxi[0, :] + s * dxi[1, :])
        omega = angular_velocity_limit * np.arctan2(-s * dxi[0, :] + c * dxi[1, :], v) / (np.pi / 2)
        return np.vstack([v, omega])

    return _created('si_to_uni_dyn', factory, SI_COMMANDS, 'dxi', si_to_uni_dyn)


def create_si_to_uni_mapping(
    projection_distance: float = 0.05, angular_velocity_limit: float = np.pi
) -> tuple[Map, Callable[[FloatArray], FloatArray]]:
    """``(si_to_uni_dyn(dxi, poses), uni_to_si_states(poses))``: the near-identity map, omega clipped to
    +/- ``angular_velocity_limit``."""
    enforce('In the function create_si_to_uni_mapping', MAPPING, locals())

    def si_to_uni_dyn(dxi: FloatArray, poses: FloatArray) -> FloatArray:
        dxu = si_to_uni(dxi, poses, projection_distance, finite=False)  # NaN and inf propagate, as in classic
        dxu[1] = np.maximum(np.minimum(dxu[1], angular_velocity_limit), -angular_velocity_limit)  # classic's order
        return dxu

    checked = _created('si_to_uni_dyn', 'create_si_to_uni_mapping', SI_COMMANDS, 'dxi', si_to_uni_dyn)

    def uni_to_si_states_(poses: FloatArray) -> FloatArray:
        _rows, _columns = np.shape(poses)  # classic unpacks the shape (1-D or None fails), then reads rows 0 to 2
        return uni_to_si_states(np.vstack([poses[0, :], poses[1, :], poses[2, :]]), projection_distance, finite=False)

    return checked, uni_to_si_states_


def create_uni_to_si_dynamics(projection_distance: float = 0.05) -> Map:
    """``uni_to_si_dyn(dxu, poses)``: the velocities of the points ``projection_distance`` ahead of the robots."""
    enforce('In the function create_uni_to_si_dynamics', UNI_TO_SI, locals())
    uni_to_si_dyn: Map = lambda dxu, poses: uni_to_si(dxu, poses, projection_distance, finite=False)
    return _created('uni_to_si_dyn', 'create_uni_to_si_dynamics', UNI_COMMANDS, 'dxu', uni_to_si_dyn)
