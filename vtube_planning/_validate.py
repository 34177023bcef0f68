"""Predicates shared by the validating constructors of the package."""

from __future__ import annotations

import math


def is_real(value: object) -> bool:
    """True for a finite int or float (bool excluded: ``True`` is not a length)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def is_positive(value: object) -> bool:
    """True for a finite number > 0."""
    return is_real(value) and value > 0  # type: ignore[operator]
