"""map_unordered on local processes (spawned): every item once, each result with its index, errors propagate."""

from __future__ import annotations

import math
import operator

import pytest

from vtube_planning.executors import map_unordered


def test_local_processes_return_every_result_with_its_index() -> None:
    items = [0.0, 1.0, 4.0, 9.0, 16.0]
    results = dict(map_unordered(math.sqrt, items, workers=2))
    assert results == {0: 0.0, 1: 1.0, 2: 2.0, 3: 3.0, 4: 4.0}


def test_an_error_in_a_local_process_propagates() -> None:
    with pytest.raises(TypeError):
        list(map_unordered(operator.neg, [1, 'x', 3], workers=2))
