"""The shape and range checks of unicycle_mapping and their exception."""

from __future__ import annotations

import numpy as np
import pytest

from unicycle_mapping.errors import MappingError, as_columns, positive


def test_as_columns_returns_a_float_array_or_names_the_shape_and_the_bad_columns() -> None:
    out = as_columns([[1, 2], [3, 4]], 2, 'x')
    assert out.dtype == np.float64 and out.shape == (2, 2)
    np.testing.assert_array_equal(out, [[1.0, 2.0], [3.0, 4.0]])
    assert as_columns(np.zeros((3, 5)), 3, 'p', 5).shape == (3, 5)
    with pytest.raises(MappingError, match=r'x must have shape \(2, N\), one robot per column; got \(3,\)'):
        as_columns(np.zeros(3), 2, 'x')
    with pytest.raises(MappingError, match=r'x must have shape \(2, 4\)'):
        as_columns(np.zeros((2, 3)), 2, 'x', 4)
    bad = np.zeros((2, 8))
    bad[1, 2], bad[0, 6] = np.inf, np.nan
    with pytest.raises(MappingError, match=r'x must be finite; columns \[2, 6\] of shape \(2, 8\)'):
        as_columns(bad, 2, 'x')


@pytest.mark.parametrize('value', [0, -1.0, float('nan'), float('inf'), True, '1', None])
def test_positive_refuses_what_is_not_a_finite_positive_number(value) -> None:
    with pytest.raises(MappingError, match=f'd must be a finite number > 0; got {value!r}'.replace('(', r'\(')):
        positive(value, 'd')


def test_positive_returns_a_float_and_the_error_is_a_value_error() -> None:
    assert positive(3, 'd') == 3.0 and isinstance(positive(3, 'd'), float)
    assert issubclass(MappingError, ValueError)
