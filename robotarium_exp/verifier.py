"""The testbed verifier's counts: as a simulator kept them, and recounted from the poses and commands it recorded.

The verifier counts, per step after the initialization, a step with any robot outside the arena, every pair of
robots too close (centres shifted forward, ``RobotariumSpec``'s collision rule), and a step with any wheel
command over the limit. V2 names its counters ``robots_outside_boundaries``, ``robots_too_close`` and
``exceeded_actuator_limits``; the classic simulator ``boundary``, ``collision`` and ``actuator``.

Beside them, the one rule of vtube's own that every verdict on a Robotarium run applies (`wall_failure`): no
robot's body on a tube wall.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.spec import ROBOTARIUM, RobotariumSpec

FloatArray = NDArray[np.float64]

BODY_ON_WALL_STEPS_TOLERATED = 0
"""Robot-steps a flight may have with a robot's body on or over a tube wall (its centre closer to the wall than
the body radius, while 0 <= l <= L): none. A body on the wall is a robot touching the tube the experiment shows it
keeps to; both shipped scenes fly with none, planned and unplanned, over the V2 initialization seeds of
docs/robotarium_compare/."""

SIMULATOR_NAMES = {
    'too_close': ('robots_too_close', 'collision'),
    'outside': ('robots_outside_boundaries', 'boundary'),
    'actuator': ('exceeded_actuator_limits', 'actuator'),
}
"""Each count's counter names in V2 and in the classic simulator."""


@dataclass(frozen=True)
class VerifierCounts:
    """What the verifier counts over a run.

    Attributes
    ----------
    too_close
        Pair-steps with two robots too close.
    outside
        Steps with a robot outside the arena (the classic simulator counts robot-steps).
    actuator
        Steps with a wheel command over the limit.
    """

    too_close: int = 0
    outside: int = 0
    actuator: int = 0

    @classmethod
    def from_simulator(cls, errors: Mapping[str, object]) -> VerifierCounts:
        """The counts of a simulator's error counters (either generation's names; texts are ignored)."""

        def total(names: tuple[str, ...]) -> int:
            return sum(int(value) for name in names if isinstance(value := errors.get(name, 0), (int, np.integer)))

        return cls(*(total(SIMULATOR_NAMES[key]) for key in ('too_close', 'outside', 'actuator')))

    @property
    def clean(self) -> bool:
        """Nothing counted: the testbed accepts the run."""
        return self.too_close == self.outside == self.actuator == 0

    def to_json(self) -> dict[str, int]:
        """The counts under V2's counter names."""
        return {SIMULATOR_NAMES[key][0]: getattr(self, key) for key in ('too_close', 'outside', 'actuator')}

    def describe(self) -> str:
        """The counts in words, for messages."""
        return (
            f'{self.too_close} pair-steps too close, {self.outside} steps outside the arena, '
            f'{self.actuator} steps over the actuator limit'
        )


def restart_shared_counters(robotarium: object) -> None:
    """Start a simulator's error counters from zero where its class shares them between instances.

    PyPI's simulator counts into a dict that is the default argument of ``_validate``: one dict for every instance
    of the process, so a second run there would report the first run's errors as its own. Emptying it when a run
    starts makes the counts read at its end this run's. Classes without such a default are left as they are.
    """
    validate = getattr(type(robotarium), '_validate', None)
    for default in getattr(validate, '__defaults__', None) or ():
        if isinstance(default, dict):
            default.clear()


def recount(poses: FloatArray, velocities: FloatArray, spec: RobotariumSpec = ROBOTARIUM) -> VerifierCounts:
    """The verifier's counts of a run from what the simulator validated each step: poses (T, 3, N) and the
    commands [v; omega] (T, 2, N) it held when ``step()`` was called."""
    outside = sum(int(spec.outside_arena(p[:2]).any()) for p in poses)
    n = poses.shape[2]
    close = 0
    if n > 1:
        heading = np.stack([np.cos(poses[:, 2]), np.sin(poses[:, 2])], axis=1)
        shifted = poses[:, :2] + spec.collision_offset_m * heading
        i, j = np.triu_indices(n, k=1)
        gaps = np.hypot(shifted[:, 0, i] - shifted[:, 0, j], shifted[:, 1, i] - shifted[:, 1, j])
        close = int(np.count_nonzero(gaps <= spec.collision_diameter_m))
    v, turn = velocities[:, 0], spec.base_length_m * velocities[:, 1]
    wheels = (1 / (2 * spec.wheel_radius_m)) * np.stack([2 * v - turn, 2 * v + turn], axis=1)
    actuator = int(np.count_nonzero((np.abs(wheels) > spec.max_wheel_speed_radps).any(axis=(1, 2))))
    return VerifierCounts(close, outside, actuator)


def closest_centres_m(poses: FloatArray) -> float:
    """The smallest distance between two robots' centres over poses (T, 3, N); infinite for one robot."""
    n = poses.shape[2]
    if n < 2 or poses.shape[0] == 0:
        return float('inf')
    i, j = np.triu_indices(n, k=1)
    return float(np.hypot(poses[:, 0, i] - poses[:, 0, j], poses[:, 1, i] - poses[:, 1, j]).min())


def wall_failure(steps: int, robots: int, max_over_m: float) -> str:
    """The failure of robot bodies on the tube walls in ``steps`` robot-steps (``robots`` robots, the deepest
    ``max_over_m`` over the wall); empty up to `BODY_ON_WALL_STEPS_TOLERATED`."""
    if steps <= BODY_ON_WALL_STEPS_TOLERATED:
        return ''
    return (
        f'robot bodies were on the tube walls in {steps} robot-steps ({robots} robots, up to {max_over_m:.3f} m over)'
    )
