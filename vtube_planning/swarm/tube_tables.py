"""The tube on a fine grid (``docs/theory.md`` §11): where a predicted point lies on the tube, and the lane a robot
flies, without searching, for the foresight's many predictions per period."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vtube_planning.geometry.tube import VirtualTube

FloatArray = NDArray[np.float64]

LOCATE_STEPS = 3
"""Newton steps of `TubeTables.locate` (from a guess a metre off, the offset is then within a millimetre)."""
TABLE_STEP_M = 0.05
"""Spacing of the tube's tables (m)."""


@dataclass(frozen=True)
class TubeTables:
    """The tube on a fine grid, past both ends by ``margin_m``: where a predicted point lies, without searching."""

    l_m: FloatArray
    stacked: FloatArray
    """Rows x, y, tangent angle, curvature and the narrowest half-width over the window ahead, (5, M) on l_m."""
    length_m: float
    slopes: FloatArray
    """Each row's change from one grid point to the next (0 after the last)."""

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
        return cls(l_m, stacked, tube.length_m, slopes)

    def at(self, l_m: FloatArray, rows: slice) -> FloatArray:
        """Rows ``rows`` of the stacked tables (x, y, angle, curvature, half-width), linearly interpolated at arc
        lengths ``l_m`` and held at the ends, like np.interp: on the uniform grid the cell is found by division,
        and all rows share it."""
        last = self.l_m.size - 1
        position = np.maximum(np.minimum((l_m - self.l_m[0]) * (last / (self.l_m[-1] - self.l_m[0])), last), 0.0)
        cell = np.minimum(position.astype(np.intp), last - 1)
        below, slope = (np.take(table[rows], cell, axis=1) for table in (self.stacked, self.slopes))
        interpolated: FloatArray = below + (position - cell) * slope
        return interpolated

    def locate(
        self, x: FloatArray, y: FloatArray, l_guess: FloatArray, steps: int = LOCATE_STEPS
    ) -> tuple[FloatArray, FloatArray]:
        """Arc length and lateral offset of points (x, y) near arc lengths ``l_guess``: ``steps`` Newton steps on
        (p - gamma(l)) . t(l) = 0, whose derivative is -(1 - kappa y) (``docs/theory.md`` §3.1)."""
        for _ in range(steps):
            centre_x, centre_y, angle, curvature = self.at(l_guess, slice(0, 4))
            dx, dy = x - centre_x, y - centre_y
            cos, sin = np.cos(angle), np.sin(angle)
            offset = dy * cos - dx * sin
            bend = 1.0 - curvature * offset
            l_guess = l_guess + (dx * cos + dy * sin) / np.maximum(bend, 0.1)
        return l_guess, offset

    def clearance(self, l_m: FloatArray, offset_m: FloatArray) -> FloatArray:
        """lambda(l) - |y|, +inf outside the tube's span 0 <= l <= L (where no wall is measured)."""
        inside = (l_m >= 0.0) & (l_m <= self.length_m)
        return np.where(inside, self.at(l_m, slice(4, 5))[0] - np.abs(offset_m), np.inf)

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
        """The lane eta a robot at (l, y) flies in now, in [-1, 1]."""
        room = np.maximum(self.at(l_m, slice(4, 5))[0] - r_s_m, 1e-9)
        lane: FloatArray = np.clip(offset_m / room, -1.0, 1.0)
        return lane
