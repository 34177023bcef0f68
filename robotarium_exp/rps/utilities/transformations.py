"""``rps.utilities.transformations`` (V2): single-integrator commands to unicycles and back.

The near-identity map (a point ``projection_distance`` ahead of the axle) is `unicycle_mapping`'s; the heading
laws are V2's. Arguments are checked with V2's messages; NaN and inf are not refused but propagate, as in V2.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from unicycle_mapping import si_to_uni, uni_to_si, uni_to_si_states

FloatArray = NDArray[np.float64]
Map = Callable[[FloatArray, FloatArray], FloatArray]


def _check_gains(linear_velocity_gain: float, angular_velocity_limit: float) -> None:
    if not (isinstance(linear_velocity_gain, (int, float)) and linear_velocity_gain > 0):
        raise AssertionError('linear_velocity_gain must be a positive number.')
    if not (isinstance(angular_velocity_limit, (int, float)) and angular_velocity_limit >= 0):
        raise AssertionError('angular_velocity_limit must be non-negative.')


def _check_projection(projection_distance: float) -> None:
    if not (isinstance(projection_distance, (int, float)) and projection_distance > 0):
        raise AssertionError('projection_distance must be a positive number.')


def _check_pair(commands: FloatArray, command_name: str, states: FloatArray, state_rows: int, state_name: str) -> None:
    """V2's shape checks of a map's arguments: ``command_name`` 2xN, ``state_name`` ``state_rows`` x N."""
    m, n = commands.shape
    ms, ns = states.shape
    if m != 2:
        raise AssertionError(f'{command_name} must be 2xN. Got {m}x{n}.')
    if ms != state_rows:
        raise AssertionError(f'{state_name} must be {state_rows}xN. Got {ms}x{ns}.')
    if n != ns:
        raise AssertionError(f'{command_name} and {state_name} must have the same number of columns ({n} vs {ns}).')


def create_si_to_uni_dynamics(linear_velocity_gain: float = 1, angular_velocity_limit: float = np.pi) -> Map:
    """The heading law (not a diffeomorphism): v = k (h . u), omega = w_lim atan2(h_perp . u, h . u) / (pi / 2)."""
    _check_gains(linear_velocity_gain, angular_velocity_limit)

    def si_to_uni_dyn(dxi: FloatArray, states: FloatArray) -> FloatArray:
        _check_pair(dxi, 'dxi', states, 3, 'states')
        c, s = np.cos(states[2]), np.sin(states[2])
        along = c * dxi[0] + s * dxi[1]
        across = -s * dxi[0] + c * dxi[1]
        return np.vstack(
            [linear_velocity_gain * along, angular_velocity_limit * np.arctan2(across, along) / (np.pi / 2)]
        )

    return si_to_uni_dyn


def create_si_to_uni_dynamics_with_backwards_motion(
    linear_velocity_gain: float = 1, angular_velocity_limit: float = np.pi
) -> Map:
    """The heading law, driving backwards when the command is not strictly within 90 degrees of the heading.

    Backwards, the law acts on the reversed heading. As in V2, omega is ``w_lim atan2(h_perp . u, v) / (pi / 2)``
    with ``v = k (h . u)``: the gain enters the angle (unlike the forward law; equal for k = 1).
    """
    _check_gains(linear_velocity_gain, angular_velocity_limit)

    def si_to_uni_dyn(dxi: FloatArray, states: FloatArray) -> FloatArray:
        _check_pair(dxi, 'dxi', states, 3, 'states')
        off = np.arctan2(dxi[1], dxi[0]) - states[2]
        off = np.arctan2(np.sin(off), np.cos(off))
        sign = np.where((off > -np.pi / 2) & (off < np.pi / 2), 1.0, -1.0)
        heading = np.where(sign > 0, states[2], states[2] + np.pi)
        c, s = np.cos(heading), np.sin(heading)
        v = linear_velocity_gain * (c * dxi[0] + s * dxi[1])
        omega = angular_velocity_limit * np.arctan2(-s * dxi[0] + c * dxi[1], v) / (np.pi / 2)
        return np.vstack([sign * v, omega])

    return si_to_uni_dyn


def create_si_to_uni_mapping(projection_distance: float = 0.05) -> tuple[Map, Callable[[FloatArray], FloatArray]]:
    """``(si_to_uni_dyn(dxi, states), uni_to_si_states(states))``: the near-identity map and its points (2xN)."""
    _check_projection(projection_distance)
    d = float(projection_distance)  # V2 takes True as 1

    def si_to_uni_dyn(dxi: FloatArray, states: FloatArray) -> FloatArray:
        _check_pair(dxi, 'dxi', states, 3, 'states')
        return si_to_uni(dxi, states, d, finite=False)  # V2: NaN and inf propagate

    def uni_to_si_states_(states: FloatArray) -> FloatArray:
        if states.shape[0] != 3:
            raise AssertionError(f'states must be 3xN. Got {states.shape[0]}x{states.shape[1]}.')
        states[0:2, :]  # V2 reads the positions: a 1-D array fails here with numpy's IndexError
        return uni_to_si_states(states, d, finite=False)

    return si_to_uni_dyn, uni_to_si_states_


def create_uni_to_si_mapping(projection_distance: float = 0.05) -> tuple[Map, Map]:
    """``(uni_to_si_dyn(dxu, states), si_to_uni_states(uni_states, si_states))``: the inverse pair.

    ``si_to_uni_states`` gives the axle positions (2xN) under the points ``si_states``.
    """
    _check_projection(projection_distance)
    d = float(projection_distance)  # V2 takes True as 1

    def uni_to_si_dyn(dxu: FloatArray, states: FloatArray) -> FloatArray:
        _check_pair(dxu, 'dxu', states, 3, 'states')
        return uni_to_si(dxu, states, d, finite=False)

    def si_to_uni_states(uni_states: FloatArray, si_states: FloatArray) -> FloatArray:
        m, n = uni_states.shape
        m_si, n_si = si_states.shape
        if m != 3:
            raise AssertionError(f'uni_states must be 3xN. Got {m}x{n}.')
        if m_si != 2:
            raise AssertionError(f'si_states must be 2xN. Got {m_si}x{n_si}.')
        if n_si != n:
            raise AssertionError(f'uni_states and si_states must have the same number of columns ({n} vs {n_si}).')
        heading = np.vstack([np.cos(uni_states[2]), np.sin(uni_states[2])])
        return si_states[:2] - d * heading

    return uni_to_si_dyn, si_to_uni_states
