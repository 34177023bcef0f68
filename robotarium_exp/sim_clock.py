"""A simulated ``time.time()`` for Robotarium scripts: it advances by the time step at each ``step()``, not by itself.

Scripts that feed wall-clock time into their control (``dt = time.time() - last``, ``while time.time() - start <
60``) give a different run on every machine and every run, on any simulator. `SimClock.install` replaces
``time.time`` for the rest of the process by a clock that starts at `START_S` and moves only when a Robotarium
steps (`ticking`: either generation's class, advancing by its own time step, 0.033 s), so such a script runs the
same everywhere; with ``rps_alias --seed`` the whole run is reproducible. ``time.perf_counter``,
``time.monotonic``, ``time.sleep`` and ``datetime`` keep the machine's clock (threads and timeouts wait on them),
and so does the simulators' own real-time pacing.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

START_S = 0.0
"""What the simulated ``time.time()`` answers before the first step."""


class SimClock:
    """A clock at ``START_S + steps * time step``: `now` is what ``time.time()`` answers once installed."""

    def __init__(self, start_s: float = START_S) -> None:
        self.now_s = float(start_s)
        self._real: Callable[[], float] | None = None

    def now(self) -> float:
        """The simulated time (s)."""
        return self.now_s

    def advance(self, dt_s: float) -> None:
        """Move the clock on by one time step ``dt_s``."""
        self.now_s += dt_s

    def install(self) -> None:
        """Make ``time.time()`` this clock's `now` (also for ``from time import time`` done afterwards)."""
        if self._real is None:
            self._real = time.time
            time.time = self.now

    def uninstall(self) -> None:
        """Give ``time.time()`` back the machine's clock."""
        if self._real is not None:
            time.time = self._real
            self._real = None


def ticking(cls: type, clock: SimClock) -> type:
    """``cls`` (either generation's Robotarium) whose every ``step()`` advances ``clock`` by the instance's time step
    (V2's ``TIME_STEP``, classic's ``time_step``)."""

    class Ticking(cls):  # type: ignore[misc, unused-ignore]  # a subclass of the class chosen at run time
        def step(self, *args: Any, **kwargs: Any) -> Any:
            result = super().step(*args, **kwargs)
            clock.advance(float(getattr(self, 'TIME_STEP', None) or self.time_step))
            return result

    Ticking.__name__ = cls.__name__
    return Ticking
