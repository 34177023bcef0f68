"""Predicates shared by the validating constructors of the package."""

from __future__ import annotations

import math

import numpy as np

from vtube_planning.errors import ShapeError


def is_real(value: object) -> bool:
    """True for a finite int or float (bool excluded: ``True`` is not a length)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def is_positive(value: object) -> bool:
    """True for a finite number > 0."""
    return is_real(value) and value > 0  # type: ignore[operator]


def as_points(
    value: object, *, name: str = 'points', item: str = 'columns', min_count: int = 0, allow_single: bool = False
) -> np.ndarray:
    """``value`` as finite float points of shape (2, N), one per column, or
    [`ShapeError`][vtube_planning.errors.ShapeError] naming the problem.

    ``allow_single`` accepts a single point of shape (2,) as (2, 1).
    """
    points = np.asarray(value, dtype=float)
    if allow_single and points.shape == (2,):
        points = points[:, None]
    if points.ndim != 2 or points.shape[0] != 2 or points.shape[1] < min_count:
        least = f' with N >= {min_count}' if min_count else ''
        msg = f'{name} must have shape (2, N){least} (one point per column); got {points.shape}.'
        raise ShapeError(msg)
    if not np.isfinite(points).all():
        bad = np.flatnonzero(~np.all(np.isfinite(points), axis=0))
        msg = f'{name} must be finite; {item} {bad[:5].tolist()} contain NaN or inf.'
        raise ShapeError(msg)
    return points
