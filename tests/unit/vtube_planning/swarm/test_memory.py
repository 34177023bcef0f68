"""The memory check: a run whose trajectory would not fit is refused before it starts, with the numbers and the
fix."""

from __future__ import annotations

import pytest

from vtube_planning.errors import ParamsError
from vtube_planning.swarm import memory
from vtube_planning.swarm.memory import LOGGED_FLOATS_PER_ROBOT, check_memory


def test_a_run_that_cannot_fit_in_memory_is_refused_before_it_starts(monkeypatch) -> None:
    need = 2 * 501 * 20 * LOGGED_FLOATS_PER_ROBOT * 8  # 501 steps of 20 robots: 1.6 MB
    monkeypatch.setattr(memory, 'available_memory_bytes', lambda: need - 1)
    with pytest.raises(ParamsError, match=r'flying 20 robots for up to 10 s .* fly fewer robots'):
        check_memory(501, 20, 10.0)
    monkeypatch.setattr(memory, 'available_memory_bytes', lambda: need)
    check_memory(501, 20, 10.0)
    monkeypatch.setattr(memory, 'available_memory_bytes', lambda: None)  # the platform does not say: no check
    check_memory(10**9, 10**6, 1e6)


def test_the_memory_available_is_a_positive_count_where_the_platform_says() -> None:
    free = memory.available_memory_bytes()
    assert free is None or free > 0
