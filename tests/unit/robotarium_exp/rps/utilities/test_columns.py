"""Arguments read robot by robot: the official loops' errors, first N columns used."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.rps.utilities.columns import multiply_each, robot_columns, robot_values


def test_the_first_n_columns_of_two_rows_or_of_one_row() -> None:
    poses = np.arange(12.0).reshape(3, 4)
    np.testing.assert_array_equal(robot_columns(poses, 3), poses[:2, :3])
    np.testing.assert_array_equal(robot_columns(poses, 2, row=2), poses[2, :2])
    np.testing.assert_array_equal(robot_values([1, 0, 1], 2), [1.0, 0.0])


@pytest.mark.parametrize(
    ('array', 'row', 'error', 'message'),
    [
        (np.zeros((3, 1)), None, IndexError, 'index 1 is out of bounds for axis 1 with size 1'),
        (np.zeros((3, 1)), 2, IndexError, 'index 1 is out of bounds for axis 1 with size 1'),
        (np.zeros((2, 2)), 2, IndexError, 'index 2 is out of bounds for axis 0 with size 2'),
        (np.zeros(3), None, IndexError, 'too many indices for array'),
        ([[0.0, 0.0], [0.0, 0.0]], None, TypeError, 'list indices must be integers or slices, not tuple'),
    ],
)
def test_what_the_official_loop_cannot_read_fails_with_its_error(array, row, error, message) -> None:
    with pytest.raises(error, match=message):
        robot_columns(array, 2, row=row)


def test_short_values_and_gains_that_cannot_multiply_fail_as_in_the_loop() -> None:
    with pytest.raises(IndexError, match='list index out of range'):
        robot_values([1], 2)
    multiply_each(1, np.int64(2), True)
    with pytest.raises(TypeError, match="can't multiply sequence by non-int of type 'numpy.float64'"):
        multiply_each(1, 'a')
    with pytest.raises(TypeError, match=r"unsupported operand type\(s\) for \*: 'NoneType' and 'float'"):
        multiply_each(None)
