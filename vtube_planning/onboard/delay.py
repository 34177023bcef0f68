"""Delay compensation: where the robots will be when a command computed now starts to act.

A command sent to a robot first waits a pure delay, then acts through a first-order lag (``docs/robotarium.md``:
the testbed's robots answer about 5 periods late, with a lag of about 0.19 s). A controller that reads the robots
where they are commands them for a past that is gone: under delay the barrier pushes overshoot, and a swarm that
is pushed apart too late collides. :class:`CommandPredictor` integrates that model of the plant from the commands
already sent, so the controller can act on where each robot will be instead.
"""

from __future__ import annotations

import math
from collections import deque
from itertools import pairwise

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def lag_response(command: FloatArray, velocity: FloatArray, h_s: float, lag_s: float) -> tuple[FloatArray, FloatArray]:
    """A first-order lag of time constant ``lag_s`` (0: none) driven by a constant ``command`` for ``h_s`` from
    ``velocity``: the mean velocity over that time (the displacement over ``h_s``) and the velocity at its end."""
    if lag_s <= 0.0:
        return command, command
    decay = math.exp(-h_s / lag_s)
    mean = command + (velocity - command) * (lag_s / h_s) * (1.0 - decay)
    return mean, command + (velocity - command) * decay


class CommandPredictor:
    """The robots' positions one delay and one lag ahead, from the commands already sent.

    The plant model: the command sent at the start of a period is held for the period, reaches the robot
    ``delay_steps`` periods later (any real number >= 0) and acts through a first-order lag of ``lag_s``; the robot
    integrates its velocity (a single integrator). :meth:`predict` integrates the model over the delay plus the lag
    (where a command's response has its centroid), with the commands not yet sent held at the last one;
    :meth:`sent` records each period's command and advances the model's velocity.

    Parameters
    ----------
    n_robots
        Swarm size.
    delay_steps, lag_s
        The plant's delay (control periods) and lag (s) to compensate.
    dt_s
        The control period.
    velocity
        The robots' velocity (2, N) before the first command, and the command they follow until it arrives; None:
        at rest.
    """

    def __init__(
        self, n_robots: int, delay_steps: float, lag_s: float, dt_s: float, velocity: FloatArray | None = None
    ) -> None:
        if not (delay_steps >= 0.0 and lag_s >= 0.0 and dt_s > 0.0):
            msg = f'delay compensation needs delay_steps >= 0, lag_s >= 0 and dt_s > 0; got {delay_steps}, {lag_s}, {dt_s}.'
            raise ValueError(msg)
        self.delay_steps, self.lag_s, self.dt_s = float(delay_steps), float(lag_s), float(dt_s)
        start = np.zeros((2, n_robots)) if velocity is None else np.array(velocity, dtype=float)
        self._sent = deque([start] * (math.ceil(self.delay_steps) + 1), maxlen=math.ceil(self.delay_steps) + 1)
        self._velocity = start.copy()  # the model's velocity at the start of this period
        self._ahead = self._pieces(self.delay_steps + self.lag_s / self.dt_s)  # where a command's response centres
        self._period = self._pieces(1.0)

    def predict(self, points: FloatArray) -> FloatArray:
        """Where the robots at ``points`` (2, N) will be a delay and a lag from now, if no new command changed it."""
        moved, _ = self._integrate(self._ahead, None)
        predicted: FloatArray = points + moved
        return predicted

    def sent(self, command: FloatArray) -> None:
        """Record the command (2, N) sent this period and advance the model's velocity to the next period."""
        command = np.array(command, dtype=float)
        _, self._velocity = self._integrate(self._period, command)
        self._sent.append(command)

    def _pieces(self, periods: float) -> list[tuple[float, int]]:
        """The spans of the next ``periods`` control periods over which one command acts: (length in periods, which
        command: 0 the one sent now, -1 the one sent last period, and so on back to the oldest kept)."""
        first = math.floor(-self.delay_steps) + 1  # commands switch where delay + k is a whole number of periods
        switches = (self.delay_steps + k for k in range(first, math.ceil(periods - self.delay_steps)))
        bounds = [0.0, *(t for t in switches if 0.0 < t < periods), periods]
        pieces: list[tuple[float, int]] = []
        for a, b in pairwise(bounds):
            age = min(max(math.floor(0.5 * (a + b) - self.delay_steps), -len(self._sent)), 0)
            if pieces and pieces[-1][1] == age:  # one command over consecutive spans: one piece
                pieces[-1] = (pieces[-1][0] + b - a, age)
            elif b > a:
                pieces.append((b - a, age))
        return pieces

    def _integrate(self, pieces: list[tuple[float, int]], current: FloatArray | None) -> tuple[FloatArray, FloatArray]:
        """The displacement and the final velocity of the model over ``pieces`` (`_pieces`) from the start of this
        period, the command sent now being ``current`` (None: not yet known, the last one held). Each piece is one
        closed-form lag response: exact for the piecewise-constant commands."""
        velocity, moved = self._velocity, np.zeros_like(self._velocity)
        for length, age in pieces:
            command = self._sent[age] if age < 0 else (current if current is not None else self._sent[-1])
            mean, velocity = lag_response(command, velocity, length * self.dt_s, self.lag_s)
            moved = moved + length * self.dt_s * mean
        return moved, velocity
