"""Timing shared by the benchmarks: median wall time over repeats, in one process."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
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


def timed_together(funs: Sequence[Callable[[], Any]], repeats: int) -> list[float]:
    """Median seconds of ``repeats`` calls of each of ``funs``, called in turn (one of each, then again): a load
    that comes and goes while they run slows them alike, so their ratios hold on a busy machine."""
    times: list[list[float]] = [[] for _ in funs]
    for _ in range(max(1, repeats)):
        for fun, own in zip(funs, times):
            start = time.perf_counter()
            fun()
            own.append(time.perf_counter() - start)
    return [sorted(own)[len(own) // 2] for own in times]
