"""Timing shared by the benchmarks: median wall time over repeats, in one process."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any


def timed(fun: Callable[[], Any], repeats: int) -> tuple[float, Any]:
    """Median seconds of ``repeats`` calls of ``fun`` (at least one), and the last call's result."""
    times, result = [], None
    for _ in range(max(1, repeats)):
        start = time.perf_counter()
        result = fun()
        times.append(time.perf_counter() - start)
    times.sort()
    return times[len(times) // 2], result
