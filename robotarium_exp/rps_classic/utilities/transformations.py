"""Classic ``rps.utilities.transformations``: single integrator <-> unicycle maps, classic names and defaults.

Three differences from V2 (:mod:`robotarium_exp.rps.utilities.transformations`), all classic's:

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
from unicycle_mapping import si_to_uni, uni_to_si, uni_to_si_states

__all__ = [
    'create_si_to_uni_dynamics',
    'create_si_to_uni_dynamics_with_backwards_motion',
    'create_si_to_uni_mapping',
    'create_uni_to_si_dynamics',
]


def create_si_to_uni_dynamics(linear_velocity_gain: float = 1, angular_velocity_limit: float = np.pi) -> Map:
    """The heading law (not a diffeomorphism): v = k (h . u), omega = w_lim atan2(h_perp . u, v) / (pi / 2), with h
    the robot's heading and h_perp its left normal; |omega| stays below 2 w_lim."""

    def si_to_uni_dyn(dxi: FloatArray, poses: FloatArray) -> FloatArray:
        c, s = np.cos(poses[2, :]), np.sin(poses[2, :])
        v = linear_velocity_gain * (c * dxi[0, :] + s * dxi[1, :])
        omega = angular_velocity_limit * np.arctan2(-s * dxi[0, :] + c * dxi[1, :], v) / (np.pi / 2)
        return np.vstack([v, omega])

    return si_to_uni_dyn


def create_si_to_uni_dynamics_with_backwards_motion(
    linear_velocity_gain: float = 1, angular_velocity_limit: float = np.pi
) -> Map:
    """Classic: the forward heading law of :func:`create_si_to_uni_dynamics`, unchanged (no backwards motion)."""
    return create_si_to_uni_dynamics(linear_velocity_gain, angular_velocity_limit)


def create_si_to_uni_mapping(
    projection_distance: float = 0.05, angular_velocity_limit: float = np.pi
) -> tuple[Map, Callable[[FloatArray], FloatArray]]:
    """``(si_to_uni_dyn(dxi, poses), uni_to_si_states(poses))``: the near-identity map, omega clipped to
    +/- ``angular_velocity_limit``."""

    def si_to_uni_dyn(dxi: FloatArray, poses: FloatArray) -> FloatArray:
        dxu = si_to_uni(dxi, poses, projection_distance)
        dxu[1] = np.clip(dxu[1], -angular_velocity_limit, angular_velocity_limit)
        return dxu

    return si_to_uni_dyn, lambda poses: uni_to_si_states(poses, projection_distance)


def create_uni_to_si_dynamics(projection_distance: float = 0.05) -> Map:
    """``uni_to_si_dyn(dxu, poses)``: the velocities of the points ``projection_distance`` ahead of the robots."""
    return lambda dxu, poses: uni_to_si(dxu, poses, projection_distance)
