"""The simulator's fault models, each off by default and drawn from its own seeded stream.

Pose noise on what the controller sees, command latency and lag, a robot failing at an arc length, and dropped messages
(neighbours avoid a robot where they last heard it). `Faults` applies them to one run, step by step.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from vtube_planning._validate import is_real
from vtube_planning.errors import ParamsError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.onboard import Projection, lag_response

FloatArray = NDArray[np.float64]

FailureMode = Literal['stop', 'coast']
FAILURE_MODES: tuple[FailureMode, ...] = ('stop', 'coast')


@dataclass(frozen=True)
class RobotFailure:
    """Robot ``robot`` fails once its arc length reaches ``at_m``: it stops dead (``'stop'``) or keeps the velocity
    it had (``'coast'``), whatever it is commanded; the others see it and must avoid it."""

    robot: int
    at_m: float
    mode: FailureMode = 'stop'

    def __post_init__(self) -> None:
        if isinstance(self.robot, bool) or not isinstance(self.robot, int) or self.robot < 0:
            msg = f'the failing robot must be a robot index >= 0; got {self.robot!r}.'
            raise ParamsError(msg)
        if not is_real(self.at_m):
            msg = f'the failure arc length at_m must be a finite number; got {self.at_m!r}.'
            raise ParamsError(msg)
        if self.mode not in FAILURE_MODES:
            msg = f'failure mode must be one of {FAILURE_MODES}; got {self.mode!r}.'
            raise ParamsError(msg)


class Faults:
    """The faults of one run as they act each control period: what the controller sees and hears, which command
    reaches the robots, and the failed robot's velocity.

    Parameters
    ----------
    seed
        The run's seed; the noise and the losses each draw from their own stream of it.
    pose_noise_m, dropout, latency_steps, lag_s, failure
        As in [`SimConfig`][vtube_planning.swarm.simulate.SimConfig].
    dt_s
        The control period (the lag's time step).
    positions, velocity
        The robots' initial positions (what they first heard of each other) and velocities (what they keep until
        the first delayed command arrives), (2, N).
    """

    def __init__(
        self,
        seed: int,
        *,
        pose_noise_m: float,
        dropout: float,
        latency_steps: int,
        lag_s: float,
        dt_s: float,
        failure: RobotFailure | None,
        positions: FloatArray,
        velocity: FloatArray,
    ) -> None:
        self.pose_noise_m, self.dropout, self.failure = pose_noise_m, dropout, failure
        self._noise = np.random.default_rng([seed, 1])  # own streams: the formation's jitter stays the same
        self._losses = np.random.default_rng([seed, 2])
        self._heard: FloatArray = positions.copy()  # where the robots last heard each other
        self._pending = deque([velocity] * latency_steps)  # commands computed, not yet applied
        self.lag_s, self.dt_s = lag_s, dt_s
        self._lagged = velocity.copy()  # the lag's output at the start of the period
        self._failed_velocity: FloatArray | None = None  # the failed robot's velocity from the failure on
        self.working = np.ones(positions.shape[1], dtype=bool)
        """The robots that count for the passage (all but a failed one)."""

    def observe(
        self, tube: VirtualTube, positions: FloatArray, projection: Projection
    ) -> tuple[FloatArray, Projection]:
        """What the controller sees of the true ``positions`` and their ``projection``: both, with pose noise."""
        if self.pose_noise_m > 0:
            seen = positions + self.pose_noise_m * self._noise.standard_normal(positions.shape)
            return seen, tube.project(seen)
        return positions, projection

    def heard(self, seen: FloatArray) -> FloatArray | None:
        """Where the robots last heard each other, the messages of this period that were not lost taken in; None
        when no message is lost."""
        if self.dropout > 0:
            arrived = self._losses.random(seen.shape[1]) >= self.dropout
            self._heard[:, arrived] = seen[:, arrived]
            return self._heard
        return None

    def delayed(self, commanded: FloatArray) -> FloatArray:
        """The velocity the robots fly this period: ``commanded`` itself, or with latency the one computed
        ``latency_steps`` periods ago, through the lag (its mean over the period) when there is one."""
        if self._pending:
            self._pending.append(commanded)
            commanded = self._pending.popleft()
        if self.lag_s > 0:
            commanded, self._lagged = lag_response(commanded, self._lagged, self.dt_s, self.lag_s)
        return commanded

    def failed(self, velocity: FloatArray, l_m: FloatArray) -> FloatArray:
        """The velocities (2, N) with the failed robot's replaced by its own, from when its arc length (in ``l_m``,
        (N,)) reached the failure's on; the robot then stops counting as working."""
        failure = self.failure
        if failure is None:
            return velocity
        if self._failed_velocity is None and l_m[failure.robot] >= failure.at_m:
            self._failed_velocity = np.zeros(2) if failure.mode == 'stop' else velocity[:, failure.robot].copy()
            self.working[failure.robot] = False
        if self._failed_velocity is not None:
            velocity = velocity.copy()
            velocity[:, failure.robot] = self._failed_velocity
        return velocity
