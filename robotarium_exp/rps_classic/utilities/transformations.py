"""Classic ``rps.utilities.transformations``: single integrator <-> unicycle maps, classic names and defaults.

Two differences from V2 (:mod:`robotarium_exp.rps.utilities.transformations`), both classic's:

* ``create_si_to_uni_mapping`` clips omega to +/- ``angular_velocity_limit`` (default pi); V2 does not clip;
* ``create_si_to_uni_dynamics_with_backwards_motion`` never drives backwards: classic's function of that name
  computes exactly the forward heading law (V2's reverses when the command points behind the robot).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from robotarium_exp.rps.utilities import transformations as v2
from robotarium_exp.rps.utilities.transformations import (
    FloatArray,
    Map,
    create_si_to_uni_dynamics,
    create_uni_to_si_dynamics,
)

__all__ = [
    'create_si_to_uni_dynamics',
    'create_si_to_uni_dynamics_with_backwards_motion',
    'create_si_to_uni_mapping',
    'create_uni_to_si_dynamics',
]


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
    return v2.create_si_to_uni_mapping(projection_distance, angular_velocity_limit)
