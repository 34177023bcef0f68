"""The tube on a fine grid (``docs/theory.md`` §11): where a predicted point lies on the tube, and the lane a robot
flies, without searching, for the foresight's many predictions per period.

Where a point lies and its clearance are compiled (numba) point by point (`locate_point`, `clearance_at`), for the
foresight's compiled predictions (`vtube_planning.swarm.foresight_kernel`) and for `TubeTables.locate` and
`TubeTables.clearance` alike; they interpolate exactly as `TubeTables.at` does (the same operations in the same
order).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np
from numpy.typing import NDArray

from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.swarm.nearest import Cells, cells, nearest_in, parallel_nearest_in

FloatArray = NDArray[np.float64]
Grid = tuple[FloatArray, FloatArray, FloatArray]
"""The tables as the compiled look-ups read them: `TubeTables.stacked`, `TubeTables.slopes`, `TubeTables.grid`."""

LOCATE_STEPS = 3
"""Newton steps of `TubeTables.locate` (from a guess a metre off, the offset is then within a millimetre)."""
TABLE_STEP_M = 0.05
"""Spacing of the tube's tables (m)."""
POINTS_PER_CELL = 20.0
"""`nearest_l`'s grid holds about this many of the tables' points a cell: a metre of a straight tube's centre, so
that a robot metres off it finds the nearest point a few cells away."""


@dataclass(frozen=True)
class TubeTables:
    """The tube on a fine grid, past both ends by ``margin_m``: where a predicted point lies, without searching."""

    l_m: FloatArray
    stacked: FloatArray
    """Rows x, y, tangent angle, curvature and the narrowest half-width over the window ahead, (5, M) on l_m."""
    length_m: float
    slopes: FloatArray
    """Each row's change from one grid point to the next (0 after the last)."""
    grid: FloatArray
    """The grid: its first arc length, grid steps per metre (as `at` scales) and its last index, (3,)."""
    points: Cells
    """The tables' centre points in cells, for `nearest_l`."""

    @classmethod
    def of(cls, tube: VirtualTube, margin_m: float, window_m: float = 0.0) -> TubeTables:
        """Tables of ``tube`` from -``margin_m`` to L + ``margin_m``; the half-width at l is the narrowest one over
        [l, l + ``window_m``]."""
        count = math.ceil((tube.length_m + 2 * margin_m) / TABLE_STEP_M) + 1
        l_m = np.linspace(-margin_m, tube.length_m + margin_m, count)
        tangent = tube.tangent(l_m)
        angle = np.unwrap(np.arctan2(tangent[:, 1], tangent[:, 0]))
        curvature = np.asarray(tube.curvature(l_m), dtype=float)
        half_width = np.asarray(tube.half_width(l_m), dtype=float)
        window = max(1, round(window_m / TABLE_STEP_M))
        padded = np.concatenate([half_width, np.full(window - 1, half_width[-1])])
        narrowest = np.lib.stride_tricks.sliding_window_view(padded, window).min(axis=1)
        stacked = np.vstack([tube.center_at(l_m).T, angle, curvature, narrowest])
        slopes = np.diff(stacked, axis=1, append=stacked[:, -1:])
        last = count - 1
        grid = np.array([l_m[0], last / (l_m[-1] - l_m[0]), last], dtype=float)
        return cls(l_m, stacked, tube.length_m, slopes, grid, cells(stacked[0], stacked[1], POINTS_PER_CELL))

    def at(self, l_m: FloatArray, rows: slice) -> FloatArray:
        """Rows ``rows`` of the stacked tables (x, y, angle, curvature, half-width), linearly interpolated at arc
        lengths ``l_m`` and held at the ends, like np.interp: on the uniform grid the cell is found by division,
        and all rows share it."""
        start_m, scale, last = self.grid[0], self.grid[1], self.l_m.size - 1
        position = np.maximum(np.minimum((l_m - start_m) * scale, last), 0.0)
        cell = np.minimum(position.astype(np.intp), last - 1)
        below, slope = (np.take(table[rows], cell, axis=1) for table in (self.stacked, self.slopes))
        interpolated: FloatArray = below + (position - cell) * slope
        return interpolated

    @property
    def compiled(self) -> Grid:
        """The tables as `locate_point` and `clearance_at` read them."""
        return self.stacked, self.slopes, self.grid

    def locate(
        self, x: FloatArray, y: FloatArray, l_guess: FloatArray, steps: int = LOCATE_STEPS
    ) -> tuple[FloatArray, FloatArray]:
        """Arc length and lateral offset of points (x, y) near arc lengths ``l_guess``, all of one shape
        (`locate_point`)."""
        shape = np.shape(x)
        x, y, l_guess = (np.ascontiguousarray(a, dtype=float).ravel() for a in (x, y, l_guess))
        l_m, offset = _locate_points(x, y, l_guess, steps, self.compiled)
        return l_m.reshape(shape), offset.reshape(shape)

    def clearance(self, l_m: FloatArray, offset_m: FloatArray) -> FloatArray:
        """lambda(l) - |y| at arc lengths and offsets of one shape, +inf outside the tube's span 0 <= l <= L, where
        no wall is measured (`clearance_at`)."""
        flat_l, flat_offset = (np.ascontiguousarray(a, dtype=float).ravel() for a in (l_m, offset_m))
        clearance: FloatArray = _clearances(flat_l, flat_offset, self.length_m, self.compiled).reshape(np.shape(l_m))
        return clearance

    def lane_heading(
        self, x: FloatArray, y: FloatArray, l_m: FloatArray, lane: FloatArray, r_s_m: float, ahead_m: FloatArray
    ) -> FloatArray:
        """The heading from (x, y), at arc length l, to the point of the lane eta ``ahead_m`` metres further along
        the tube (pure pursuit: it turns into a narrowing or a bend before the robot gets there)."""
        centre_x, centre_y, angle, _, half_width = self.at(l_m + ahead_m, slice(0, 5))
        lateral = lane * np.maximum(half_width - r_s_m, 0.0)
        goal_x = centre_x - lateral * np.sin(angle)
        goal_y = centre_y + lateral * np.cos(angle)
        heading: FloatArray = np.arctan2(goal_y - y, goal_x - x)
        return heading

    def lane_of(self, l_m: FloatArray, offset_m: FloatArray, r_s_m: float) -> FloatArray:
        """The lane eta robots at arc lengths and offsets (l, y) (N,) fly in now, in [-1, 1]: y over the room
        lambda(l) - r_s (at least 1e-9)."""
        lane: FloatArray = _lanes(np.ascontiguousarray(l_m), np.ascontiguousarray(offset_m), r_s_m, self.compiled)
        return lane

    def nearest_l(self, positions: FloatArray, *, all_cores: bool = False) -> FloatArray:
        """The arc length of the tables' point nearest to each position (2, N): where `locate` starts (searched on
        all cores or on one: `vtube_planning.swarm.nearest`)."""
        x, y = np.ascontiguousarray(positions, dtype=float)
        search = parallel_nearest_in if all_cores else nearest_in
        return self.l_m[search(self.points, x, y, self.stacked[0], self.stacked[1], 1)[:, 0]]


@numba.njit(cache=True, inline='always')
def minimum(a: float, b: float) -> float:
    """np.minimum of two numbers (a NaN propagates)."""
    return a if (a < b or math.isnan(a)) else b


@numba.njit(cache=True, inline='always')
def maximum(a: float, b: float) -> float:
    """np.maximum of two numbers (a NaN propagates)."""
    return a if (a > b or math.isnan(a)) else b


@numba.njit(cache=True)
def table_row(l_m: float, row: int, tables: Grid) -> float:
    """Row ``row`` of the tables at arc length ``l_m``, as `TubeTables.at` interpolates it (held at the ends)."""
    stacked, slopes, grid = tables
    last = int(grid[2])
    position = maximum(minimum((l_m - grid[0]) * grid[1], float(last)), 0.0)
    cell = min(int(position), last - 1)
    value: float = stacked[row, cell] + (position - float(cell)) * slopes[row, cell]
    return value


@numba.njit(cache=True)
def locate_point(x: float, y: float, l_guess: float, steps: int, tables: Grid) -> tuple[float, float]:
    """Arc length and lateral offset of the point (x, y) near arc length ``l_guess``: ``steps`` Newton steps on
    (p - gamma(l)) . t(l) = 0, whose derivative is -(1 - kappa y) (``docs/theory.md`` §3.1)."""
    offset = 0.0
    for _ in range(steps):
        angle = table_row(l_guess, 2, tables)
        dx, dy = x - table_row(l_guess, 0, tables), y - table_row(l_guess, 1, tables)
        cos, sin = math.cos(angle), math.sin(angle)
        offset = dy * cos - dx * sin
        bend = 1.0 - table_row(l_guess, 3, tables) * offset
        l_guess = l_guess + (dx * cos + dy * sin) / maximum(bend, 0.1)
    return l_guess, offset


@numba.njit(cache=True)
def clearance_at(l_m: float, offset_m: float, length_m: float, tables: Grid) -> float:
    """lambda(l) - |y| at arc length ``l_m`` and offset ``offset_m``, +inf outside 0 <= l <= ``length_m``."""
    if 0.0 <= l_m <= length_m:
        return table_row(l_m, 4, tables) - abs(offset_m)
    return math.inf


@numba.njit(cache=True)
def _locate_points(
    x: FloatArray, y: FloatArray, l_guess: FloatArray, steps: int, tables: Grid
) -> tuple[FloatArray, FloatArray]:
    """`locate_point` of each point."""
    l_m, offset = np.empty(x.size), np.empty(x.size)
    for i in range(x.size):
        l_m[i], offset[i] = locate_point(x[i], y[i], l_guess[i], steps, tables)
    return l_m, offset


@numba.njit(cache=True)
def _lanes(l_m: FloatArray, offset_m: FloatArray, r_s_m: float, tables: Grid) -> FloatArray:
    """`TubeTables.lane_of`, point by point."""
    out = np.empty(l_m.size)
    for i in range(l_m.size):
        room = maximum(table_row(l_m[i], 4, tables) - r_s_m, 1e-9)
        out[i] = minimum(maximum(offset_m[i] / room, -1.0), 1.0)
    return out


@numba.njit(cache=True)
def _clearances(l_m: FloatArray, offset_m: FloatArray, length_m: float, tables: Grid) -> FloatArray:
    """`clearance_at` of each point."""
    out = np.empty(l_m.size)
    for i in range(l_m.size):
        out[i] = clearance_at(l_m[i], offset_m[i], length_m, tables)
    return out
