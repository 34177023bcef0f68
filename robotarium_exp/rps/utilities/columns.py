"""Arguments read robot by robot, as the official utilities' loops read them: their errors, in their order.

The official utilities loop over the robots (``for i in range(N)``) and index each argument per robot
(``poses[2, i]``, ``states[:2, i]``, ``approach_state[i]``); ours compute all robots at once. To fail where the
official fails, with the same error, ours first read each argument with these helpers: a list, a 1-D array, a
missing row or column raises the ``TypeError`` or ``IndexError`` the official's first such read raises, and an
argument with more columns than robots is used only for its first N, as the official uses it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def robot_columns(array: Any, n: int, row: int | None = None) -> FloatArray:
    """The first ``n`` columns of ``array``'s ``row`` (or of its first two rows), as float."""
    rows = array[:2, :] if row is None else array[row, :]
    width = rows.shape[-1]
    if width < n:  # the official's loop stops at the first missing column with numpy's IndexError
        array[:2, width] if row is None else array[row, width]
    return np.asarray(rows[..., :n], dtype=float)


def robot_values(values: Any, n: int) -> FloatArray:
    """The first ``n`` of ``values`` (a list or an array), as float."""
    if len(values) < n:
        values[len(values)]  # the official's loop stops here with Python's or numpy's IndexError
    return np.asarray(values[:n], dtype=float)


def multiply_each(*gains: Any) -> None:
    """Multiply each gain with a float64 and store it in a float array, as the official's per-robot loops do, in
    order: a ``str`` or ``None`` gain fails here with the official's ``TypeError``."""
    np.zeros(len(gains))[:] = [gain * np.float64(1.0) for gain in gains]
