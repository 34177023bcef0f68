"""``rps.utilities.transformations`` of both generations, on :mod:`unicycle_mapping`."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from unicycle_mapping import si_to_uni, si_to_uni_states, uni_to_si, uni_to_si_states

FloatArray = NDArray[np.float64]
Map = Callable[[FloatArray, FloatArray], FloatArray]


def create_si_to_uni_dynamics(linear_velocity_gain: float = 1, angular_velocity_limit: float = np.pi) -> Map:
    """V2 heading law (not a diffeomorphism): v = k (h . u), omega = w_lim atan2(h_perp . u, h . u) / (pi / 2)."""

    def dynamics(dxi: FloatArray, poses: FloatArray) -> FloatArray:
        c, s = np.cos(poses[2]), np.sin(poses[2])
        along = c * dxi[0] + s * dxi[1]
        across = -s * dxi[0] + c * dxi[1]
        return np.vstack(
            [linear_velocity_gain * along, angular_velocity_limit * np.arctan2(across, along) / (np.pi / 2)]
        )

    return dynamics


def create_si_to_uni_dynamics_with_backwards_motion(
    linear_velocity_gain: float = 1, angular_velocity_limit: float = np.pi
) -> Map:
    """V2: the heading law, reversing when the command points more than 90 degrees away."""
    forward = create_si_to_uni_dynamics(linear_velocity_gain, angular_velocity_limit)

    def dynamics(dxi: FloatArray, poses: FloatArray) -> FloatArray:
        flipped = poses.copy()
        behind = np.cos(poses[2]) * dxi[0] + np.sin(poses[2]) * dxi[1] < 0
        flipped[2, behind] += np.pi
        dxu = forward(dxi, flipped)
        dxu[0, behind] *= -1
        return dxu

    return dynamics


def create_si_to_uni_mapping(
    projection_distance: float = 0.05, angular_velocity_limit: float | None = None
) -> tuple[Map, Callable[[FloatArray], FloatArray]]:
    """``(si_to_uni_dyn(dxi, poses), uni_to_si_states(poses))``: the near-identity map.

    V2 applies no limit to omega; the classic version clips it to ``angular_velocity_limit`` (pass it to get that).
    """

    def si_to_uni_dyn(dxi: FloatArray, poses: FloatArray) -> FloatArray:
        dxu = si_to_uni(dxi, poses, projection_distance)
        if angular_velocity_limit is not None:
            dxu[1] = np.clip(dxu[1], -angular_velocity_limit, angular_velocity_limit)
        return dxu

    return si_to_uni_dyn, lambda poses: uni_to_si_states(poses, projection_distance)


def create_uni_to_si_mapping(projection_distance: float = 0.05) -> tuple[Map, Map]:
    """V2: ``(uni_to_si_dyn(dxu, poses), si_to_uni_states(uni_states, si_states))``."""

    def states(uni_states: FloatArray, si_states: FloatArray) -> FloatArray:
        return si_to_uni_states(si_states, uni_states[2], projection_distance)

    return (lambda dxu, poses: uni_to_si(dxu, poses, projection_distance)), states


def create_uni_to_si_dynamics(projection_distance: float = 0.05) -> Map:
    """Classic: ``uni_to_si_dyn(dxu, poses)`` alone."""
    return lambda dxu, poses: uni_to_si(dxu, poses, projection_distance)
