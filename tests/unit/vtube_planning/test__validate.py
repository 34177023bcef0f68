"""The shared predicates: real and positive numbers, (2, N) point arrays with the problem named."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vtube_planning._validate import as_points, is_positive, is_real
from vtube_planning.errors import ShapeError


@pytest.mark.parametrize(
    ('value', 'real', 'positive'),
    [
        (1, True, True),
        (2.5, True, True),
        (0, True, False),
        (-3.0, True, False),
        (True, False, False),
        (math.inf, False, False),
        (math.nan, False, False),
        ('1', False, False),
        (None, False, False),
        (np.float64(2.0), True, True),
    ],
)
def test_real_and_positive(value: object, real: bool, positive: bool) -> None:
    assert bool(is_real(value)) is real and bool(is_positive(value)) is positive


def test_points_come_back_as_float_columns() -> None:
    points = as_points([[0, 1, 2], [3, 4, 5]])
    assert points.dtype == float and points.shape == (2, 3)
    assert as_points([1.0, 2.0], allow_single=True).shape == (2, 1)
    assert as_points(np.zeros((2, 0))).shape == (2, 0)


@pytest.mark.parametrize(
    ('value', 'kwargs', 'match'),
    [
        ([1.0, 2.0], {}, r'points must have shape \(2, N\) \(one point per column\); got \(2,\)'),
        (np.zeros((3, 2)), {'name': 'robots'}, r'robots must have shape \(2, N\) .* got \(3, 2\)'),
        (np.zeros((2, 1)), {'min_count': 2}, r'shape \(2, N\) with N >= 2 .* got \(2, 1\)'),
        ([[0.0, np.nan, 1.0], [0.0, 0.0, np.inf]], {'item': 'robots'}, r'must be finite; robots \[1, 2\] contain'),
    ],
)
def test_bad_points_are_named(value: object, kwargs: dict, match: str) -> None:
    with pytest.raises(ShapeError, match=match):
        as_points(value, **kwargs)
