"""The state V2's initialization leaves in the simulator, for a host that runs many scripts from the same start.

V2's initialization (`robotarium_exp.rps.robotarium.Robotarium.initialize`) is a function of the robots' count,
the initial conditions, the poses on the chargers (Python's ``random`` drew them; the initialization draws only
from ``np.random``), the state of ``np.random`` at its start, the distance sensors and obstacles, the QP solver and
cvxopt's options, and the simulator's code. Whatever runs after it (the script's loop, under any testbed model:
the initialization stays ideal) starts from what it leaves: the poses, the sensors, the counters and the state of
``np.random``. A host that runs the same start many times (the preflight: each seed under several testbed models,
and again after a change of the script's control) sets `memo`; the simulator then takes that state from it where
it holds the same inputs (`key`), bit for bit what the initialization would have left, and gives it the state
otherwise (`initialize_or_recall`). The host adds to the key what the simulator cannot see (its sources, the
libraries' versions).
"""

from __future__ import annotations

import hashlib
from typing import Any, Protocol

import cvxopt
import numpy as np
from numpy.typing import NDArray

from robotarium_exp.rps.utilities.barrier_certificates import qp_solver

State = dict[str, NDArray[Any]]

FIELDS = (
    '_velocities',
    '_velocities_old',
    '_poses',
    '_distances',
    '_accelerations',
    '_orientations',
    '_magnetic_fields',
    '_gyros',
    '_encoders',
    '_leds',
    '_distance_endpoints',
    '_iteration',
    '_called_step_already',
    '_checked_poses_already',
)
"""The simulator's attributes the initialization changes (its error counts stay empty: nothing is validated)."""


class InitializationMemo(Protocol):
    """Where a host keeps initialized states by their key; ``salt``: what the host adds to every key."""

    salt: bytes

    def recall(self, key: str) -> State | None:
        """The state stored under ``key``, or None."""

    def keep(self, key: str, state: State) -> None:
        """Store ``state`` under ``key``."""


memo: InitializationMemo | None = None
"""Set by a host that runs many scripts from the same start; None: every construction initializes."""


def initialize_or_recall(robot: Any, step_limit: int) -> None:
    """``robot.initialize`` to its initial conditions (``step_limit``: the steps after which it is stuck), or the
    state that would leave taken from `memo` where it holds it (headless only: a figure is not recalled)."""
    chosen = None if robot.show_figure else memo
    if chosen is None:
        robot.initialize(robot.initial_conditions)
        return
    found = key(robot, robot.initial_conditions, chosen.salt, step_limit)
    state = chosen.recall(found)
    if state is None or not restore(robot, state):
        robot.initialize(robot.initial_conditions)
        chosen.keep(found, state_of(robot))


def key(robot: Any, initial_conditions: NDArray[np.float64], salt: bytes, step_limit: int) -> str:
    """The sha256 of everything the initialization of ``robot`` (constructed, its poses on the chargers) to
    ``initial_conditions`` within ``step_limit`` steps depends on that the simulator sees, and ``salt``."""
    digest = hashlib.sha256(salt)
    name, keys, position, has_gauss, cached = np.random.get_state(legacy=True)
    digest.update(
        repr(
            (robot.number_of_robots, name, position, has_gauss, cached, qp_solver())
            + (robot._distance_sensors_enabled, step_limit)
            + (sorted((str(k), repr(v)) for k, v in cvxopt.solvers.options.items()),)
        ).encode()
    )
    for array in (keys, robot._poses, initial_conditions, robot.obstacles):
        digest.update(b'\0' if array is None else np.ascontiguousarray(array).tobytes())
    return digest.hexdigest()


def state_of(robot: Any) -> State:
    """What the initialization left in ``robot`` and in ``np.random``."""
    _, keys, position, has_gauss, cached = np.random.get_state(legacy=True)
    state = {field: np.array(getattr(robot, field)) for field in FIELDS}
    return state | {
        'numpy_keys': np.array(keys, dtype=np.uint32),
        'numpy_rest': np.array([position, has_gauss, cached], dtype=np.float64),
    }


def restore(robot: Any, state: State) -> bool:
    """Put ``state`` (`state_of`) back into ``robot`` and ``np.random``; False (nothing changed) when it is not
    such a state for ``robot`` (a field missing, of another shape or kind)."""
    expected = state_of(robot)
    for name, value in expected.items():
        found = state.get(name)
        if not isinstance(found, np.ndarray) or found.shape != value.shape or found.dtype.kind != value.dtype.kind:
            return False
    for field in FIELDS:
        value = state[field]
        setattr(robot, field, value.copy() if value.ndim else value.item())
    robot._moving = robot._velocities  # what moved the robots in the last step: the command (no model acts yet)
    position, has_gauss, cached = state['numpy_rest']
    np.random.set_state(('MT19937', state['numpy_keys'], int(position), int(has_gauss), float(cached)))
    return True
