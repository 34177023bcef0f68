"""Exceptions of `unicycle_mapping` and the shape checks that raise them."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


class MappingError(ValueError):
    """Bad input to the mapping: wrong shape, non-finite values, or a parameter out of range."""


def as_columns(
    value: ArrayLike, rows: int, name: str, n: int | None = None, *, finite: bool = True
) -> NDArray[np.float64]:
    """``value`` as a float array of shape (rows, N), finite unless ``finite`` is False, or :class:`MappingError`
    naming the shape (or the columns holding NaN or inf)."""
    arr = np.asarray(value, dtype=float)
    if arr.ndim != 2 or arr.shape[0] != rows or (n is not None and arr.shape[1] != n):
        expected = f'({rows}, {n})' if n is not None else f'({rows}, N)'
        msg = f'{name} must have shape {expected}, one robot per column; got {arr.shape}.'
        raise MappingError(msg)
    if finite and not np.all(np.isfinite(arr)):
        bad = np.flatnonzero(~np.all(np.isfinite(arr), axis=0))
        msg = f'{name} must be finite; columns {bad[:5].tolist()} of shape {arr.shape} hold NaN or inf.'
        raise MappingError(msg)
    return arr


def positive(value: float, name: str) -> float:
    """``value`` as a float if it is finite and > 0, else :class:`MappingError`."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value) or value <= 0:
        msg = f'{name} must be a finite number > 0; got {value!r}.'
        raise MappingError(msg)
    return float(value)
