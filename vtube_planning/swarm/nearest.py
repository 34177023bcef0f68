"""The k nearest of a set of points, compiled (numba): what a k-d tree query answers, found in a uniform grid.

The foresight asks it every period, twice: each robot's nearest robots (the neighbours it checks) and the nearest
point of the tube's tables (where its arc length is looked for). Distances are compared squared, dx^2 + dy^2, as
scipy's k-d tree compares them, so both find the same points (points equally far at the k-th place aside); a grid
of the points, searched in rings of cells around each query until no cell further out can hold a nearer point,
costs a period of 10,000 robots about a third of the tree's query.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]
Cells = tuple[float, float, float, int, int, IntArray, IntArray]
"""A grid of points (`cells`): its corner, cell side, columns and rows, each cell's first place in the order
(``starts``, one past the last at the end) and the points in cell order."""
PER_CELL = 0.25
"""`nearest` makes its grid's cells hold about `PER_CELL` k points each."""


@numba.njit(cache=True)
def cells(x: FloatArray, y: FloatArray, per_cell: float) -> Cells:
    """The points sorted into a uniform grid over their bounding box, about ``per_cell`` points a cell: spread over
    the box, or along its longer side where they lie on a line (a straight tube's centre)."""
    low_x, low_y = x.min(), y.min()
    span_x, span_y = max(x.max() - low_x, 1e-9), max(y.max() - low_y, 1e-9)
    spread = math.sqrt(span_x * span_y * per_cell / x.size)
    side = max(spread, max(span_x, span_y) * per_cell / x.size, 1e-9)
    columns = min(int(span_x / side) + 1, 4 * x.size)
    rows = min(int(span_y / side) + 1, 4 * x.size)
    side = max(side, span_x / columns, span_y / rows)  # about N / per_cell cells, however thin the box
    cell = np.empty(x.size, dtype=np.intp)
    starts = np.zeros(columns * rows + 1, dtype=np.intp)
    for i in range(x.size):
        column = min(int((x[i] - low_x) / side), columns - 1)
        cell[i] = min(int((y[i] - low_y) / side), rows - 1) * columns + column
        starts[cell[i] + 1] += 1
    for c in range(columns * rows):
        starts[c + 1] += starts[c]
    order, filled = np.empty(x.size, dtype=np.intp), starts[:-1].copy()
    for i in range(x.size):
        order[filled[cell[i]]] = i
        filled[cell[i]] += 1
    return low_x, low_y, side, columns, rows, starts, order


def nearest(
    query_x: FloatArray, query_y: FloatArray, x: FloatArray, y: FloatArray, k: int, *, all_cores: bool = False
) -> IntArray:
    """(Q, k) the indices of the k points (``x``, ``y``) nearest to each query point, nearest first (k at most the
    number of points), on one core or on all (`parallel_nearest_in`). A query that is one of the points finds
    itself first."""
    search = parallel_nearest_in if all_cores else nearest_in
    found: IntArray = search(cells(x, y, PER_CELL * k), query_x, query_y, x, y, k)
    return found


@numba.njit(cache=True)
def nearest_in(grid: Cells, query_x: FloatArray, query_y: FloatArray, x: FloatArray, y: FloatArray, k: int) -> IntArray:
    """`nearest`, in a grid of the points made before (`cells`)."""
    low_x, low_y, side, columns, rows, starts, order = grid
    found = np.empty((query_x.size, k), dtype=np.intp)
    for i in numba.prange(query_x.size):
        best, index = np.empty(k), np.empty(k, dtype=np.intp)
        qx, qy, count = query_x[i], query_y[i], 0
        column = min(max(math.floor((qx - low_x) / side), 0), columns - 1)
        row = min(max(math.floor((qy - low_y) / side), 0), rows - 1)
        gap_x = max(low_x - qx, qx - (low_x + columns * side), 0.0)  # how far outside the grid the query lies
        gap_y = max(low_y - qy, qy - (low_y + rows * side), 0.0)
        ring = 0
        while True:
            for r in range(max(row - ring, 0), min(row + ring, rows - 1) + 1):
                step = 1 if r in (row - ring, row + ring) else max(2 * ring, 1)  # inside the ring: its two sides
                for c in range(column - ring, column + ring + 1, step):
                    if c < 0 or c >= columns:
                        continue
                    for place in range(starts[r * columns + c], starts[r * columns + c + 1]):
                        j = order[place]
                        dx, dy = qx - x[j], qy - y[j]
                        squared = dx * dx + dy * dy
                        if count == k and squared >= best[k - 1]:
                            continue
                        slot = min(count, k - 1)
                        while slot > 0 and best[slot - 1] > squared:
                            best[slot], index[slot] = best[slot - 1], index[slot - 1]
                            slot -= 1
                        best[slot], index[slot] = squared, j
                        count = min(count + 1, k)
            if ring >= max(row, rows - 1 - row, column, columns - 1 - column):
                break  # the whole grid searched
            # every point of a cell further out lies at least this far: ring cells beside or above the query's
            further = ring * side
            reach = min((gap_x + further) ** 2 + gap_y**2, gap_x**2 + (gap_y + further) ** 2)
            if count == k and best[k - 1] <= reach:
                break
            ring += 1
        found[i] = index
    return found


parallel_nearest_in = numba.njit(parallel=True)(nearest_in.py_func)
"""`nearest_in` on all cores (numba's threads, one query each): the same points, for large swarms; compiled on
first use (not cached: a cache of the same function's serial build would be read back for it)."""
