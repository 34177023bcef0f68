"""Classic's checks as data: the first failing check names the place, in order; created functions are checked."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.rps_classic.utilities.checks import POSITIVE, Checked, bound, enforce, pair, rows, typed

CHECKS = (typed('k', 'the gain (k)'), bound('k', 'the gain (k)', POSITIVE))


def test_the_first_failing_check_raises_its_message_after_the_place() -> None:
    with pytest.raises(
        AssertionError, match=r"^In f, the gain \(k\) must be an integer or float. Recieved type 'str'.$"
    ) as caught:
        enforce('In f', CHECKS, {'k': 'a'})
    assert caught.type is AssertionError  # classic's assert: the same last traceback line
    with pytest.raises(AssertionError, match=r'^In f, the gain \(k\) must be positive. Recieved -1.$'):
        enforce('In f', CHECKS, {'k': -1})
    enforce('In f', CHECKS, {'k': 2})


def test_a_check_reads_its_argument_as_classic_does() -> None:
    with pytest.raises(AttributeError, match="'list' object has no attribute 'shape'"):
        enforce('In f', (rows('x', 2, 'x must be 2'),), {'x': [[0.0]]})


def test_a_checked_function_checks_then_answers_and_forwards_its_attributes() -> None:
    def add(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return a + b

    add.stats = 'counted'  # type: ignore[attr-defined]
    checked = Checked(add, pair('In g', (rows('a', 2, 'the dimension of a must be 2'),), 'a', 'b'))
    assert checked(np.ones(2), np.ones(2)).tolist() == [2.0, 2.0]
    assert checked.stats == 'counted'
    with pytest.raises(AssertionError, match=r'^In g, the dimension of a must be 2. Recieved dimension 3.$'):
        checked(np.ones(3), np.ones(3))
