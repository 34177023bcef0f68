"""V2's certificates' arguments, reached as V2 reaches them: its errors, its numbers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robotarium_exp.rps.errors import RobotariumError
from robotarium_exp.rps.utilities.barrier_inputs import (
    V2_BOUNDARY,
    V2Arguments,
    checked_pair,
    one_row_rows,
    v2_positions,
)
from robotarium_exp.rps.utilities.barrier_rows import BarrierSpec, barrier_rows


def test_numbers_v2_can_compute_with_are_taken_as_given() -> None:
    spec = V2Arguments(np.float32(0.1), -1, True).spec()
    assert (spec.safety_radius, spec.barrier_gain, spec.magnitude_limit) == (float(np.float32(0.1)), -1.0, 1.0)
    assert spec.boundary is None and spec.full_first_side and spec.speed_polygon
    walled = V2Arguments(0.15, 100, 0.2, [-1.0, 1.0, -1.0, 1.0]).spec()
    assert walled.boundary == (-1.0, 1.0, -1.0, 1.0) and not walled.full_first_side
    assert V2Arguments(0.15, 100, 0.2, V2_BOUNDARY).spec().boundary == V2_BOUNDARY


@pytest.mark.parametrize(
    ('arguments', 'error', 'message'),
    [
        (V2Arguments('a', 100, 0.2), TypeError, r"for \*\* or pow\(\): 'str' and 'int'"),
        (V2Arguments(0.15, 'a', 0.2), TypeError, "can't multiply sequence by non-int of type 'numpy.float64'"),
        (V2Arguments(0.15, 100, 'a'), ValueError, "could not convert string to float: 'a'"),
        (V2Arguments(0.15, 100, None), TypeError, r"for \*: 'NoneType' and 'float'"),
        (V2Arguments(0.15, 100, 0.2, np.zeros(3)), IndexError, 'index 3 is out of bounds for axis 0 with size 3'),
    ],
)
def test_a_value_v2_cannot_compute_with_fails_with_v2s_error(arguments, error, message) -> None:
    with pytest.raises(error, match=message):
        arguments.spec()


def test_positions_are_the_first_two_rows_and_n_columns_with_v2s_errors() -> None:
    x = np.arange(12.0).reshape(3, 4)
    np.testing.assert_array_equal(v2_positions(x, 3, walls=False), x[:2, :3])
    with pytest.raises(IndexError, match='index 4 is out of bounds for axis 1 with size 4'):
        v2_positions(x, 5, walls=False)
    with pytest.raises(IndexError, match='index 1 is out of bounds for axis 0 with size 1'):
        v2_positions(np.zeros((1, 2)), 2, walls=True)
    with pytest.raises(ValueError, match=r'could not broadcast input array from shape \(0,\) into shape \(2,\)'):
        v2_positions(np.zeros((0, 2)), 2, walls=True)  # V2's first pair row, before its walls
    with pytest.warns(RuntimeWarning, match=r'x has one row \(shape \(1, 3\)\).*give x as 2xN'):
        one_row = v2_positions(np.arange(3.0)[None, :], 2, walls=False)
    np.testing.assert_array_equal(one_row, [[0.0, 1.0]])


def test_one_row_of_positions_is_read_as_v2_reads_it() -> None:
    """V2's loops written out for x (1, 3): each pair's row -2 (d, d) at i and +2 (d, d) at j, its bound
    gamma (d^2 - R^2)^3; then the speed polygon of two-row positions."""
    x = np.array([[0.0, 0.2, 0.5]])
    spec = BarrierSpec(0.15, 100.0, 0.2, None, True)
    a, b = one_row_rows(x, spec)
    for pair, (i, j) in enumerate([(0, 1), (0, 2), (1, 2)]):
        d = x[0, i] - x[0, j]
        row = np.zeros(6)
        row[2 * i : 2 * i + 2], row[2 * j : 2 * j + 2] = -2 * d, 2 * d
        np.testing.assert_array_equal(a[pair], row)
        assert b[pair] == pytest.approx(100.0 * (d * d - 0.15**2) ** 3, rel=1e-14)  # a power of an array
    polygon_a, polygon_b = barrier_rows(np.zeros((2, 3)), spec)
    np.testing.assert_array_equal(a[3:], polygon_a[3:])
    np.testing.assert_array_equal(b[3:], polygon_b[3:])


def test_classic_inputs_must_be_finite_arrays_of_one_width() -> None:
    u, x = checked_pair(np.zeros((2, 2)), np.ones((3, 2)), 'dxu', 'x', state_rows=3)
    assert u.shape == (2, 2) and x.shape == (3, 2)
    with pytest.raises(RobotariumError, match='must be finite'):
        checked_pair(np.full((2, 2), math.nan), np.ones((2, 2)), 'dxi', 'x')
