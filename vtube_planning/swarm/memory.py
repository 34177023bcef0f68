"""Whether a simulated run's trajectory fits the memory available: refused before it starts, not midway."""

from __future__ import annotations

import os

from vtube_planning.errors import ParamsError

LOGGED_FLOATS_PER_ROBOT = 10
"""Per robot and step the simulation keeps positions, velocities and commands (2 each), r_a, l, clearance and the
forward speed: 10 floats, twice while they are stacked into arrays."""


def available_memory_bytes() -> int | None:
    """The physical memory not in use now (None where the platform does not say)."""
    try:
        return int(os.sysconf('SC_AVPHYS_PAGES')) * int(os.sysconf('SC_PAGE_SIZE'))
    except (AttributeError, ValueError, OSError):
        return None


def check_memory(steps: int, n: int, limit_s: float) -> None:
    """Refuse a run whose trajectory, kept to the time limit, would not fit the memory available."""
    need = 2 * steps * n * LOGGED_FLOATS_PER_ROBOT * 8
    free = available_memory_bytes()
    if free is not None and need > free:
        msg = (
            f'flying {n} robots for up to {limit_s:.0f} s (the time limit) keeps about {need / 2**30:.1f} GiB of '
            f'trajectory in memory, more than the {free / 2**30:.1f} GiB available; fly fewer robots, or set a '
            'shorter time_limit_s.'
        )
        raise ParamsError(msg)
