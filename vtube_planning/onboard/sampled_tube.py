"""The tube as samples, what a submission carries: :class:`SampledTube` (numpy only)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from vtube_planning.onboard.projection import Projection

FloatArray = NDArray[np.float64]


class SampledTube:
    """A tube given by samples: centre-line points, half-widths and cumulative areas at arc lengths.

    Between samples the centre line is the polyline through them, and the half-width and the area are linear.
    With samples 1 cm apart on the Robotarium scenes, offsets agree with the exact tube to 0.2 mm and arc lengths
    to |y| kappa h / 2, under 2 mm (``tests/unit/vtube_planning/onboard/test_sampled_tube.py``).

    Parameters
    ----------
    l_m
        Increasing arc lengths of the samples, (K,), from 0 to L.
    xy_m
        Centre-line points, (2, K).
    half_width_m, area_m2
        lambda and the cumulative area A at the samples, (K,).
    """

    def __init__(self, l_m: ArrayLike, xy_m: ArrayLike, half_width_m: ArrayLike, area_m2: ArrayLike) -> None:
        self.l_m = np.asarray(l_m, dtype=float)
        self.xy_m = np.asarray(xy_m, dtype=float)
        self.half_width_m = np.asarray(half_width_m, dtype=float)
        self.area_m2 = np.asarray(area_m2, dtype=float)
        segment = np.diff(self.xy_m, axis=1)
        self._seg_len = np.hypot(segment[0], segment[1])
        self._seg_dir = segment / self._seg_len

    @property
    def length_m(self) -> float:
        """L, the arc length of the last sample."""
        return float(self.l_m[-1])

    def project(self, points_m: ArrayLike) -> Projection:
        """Closest point of the polyline to every column of (2, N) points; beyond the ends, the end segments' lines."""
        points = np.asarray(points_m, dtype=float)
        rel = points[:, :, None] - self.xy_m[:, None, :-1]  # (2, N, K-1)
        along = np.clip(np.einsum('ink,ik->nk', rel, self._seg_dir), 0.0, self._seg_len)
        foot = self.xy_m[:, None, :-1] + self._seg_dir[:, None, :] * along
        k = np.argmin(np.hypot(*(points[:, :, None] - foot)), axis=1)
        s = along[np.arange(points.shape[1]), k]
        tangent = self._seg_dir[:, k]
        base = self.xy_m[:, k]
        before = (k == 0) & (s <= 0.0)
        after = (k == self._seg_len.size - 1) & (s >= self._seg_len[-1])
        s = np.where(before | after, np.einsum('in,in->n', points - base, tangent), s)
        l_m = self.l_m[k] + s
        foot_m = base + tangent * s
        normal = np.vstack([-tangent[1], tangent[0]])
        return Projection(
            l_m=l_m,
            y_m=np.einsum('in,in->n', points - foot_m, normal),
            foot_m=foot_m,
            tangent=tangent,
            normal=normal,
            half_width_m=np.interp(l_m, self.l_m, self.half_width_m),
            length_m=self.length_m,
            curvature_per_m=np.zeros(l_m.size),  # the polyline is straight between its samples
        )

    def project_near(self, points_m: ArrayLike, near: Projection) -> Projection:
        """:meth:`project`; the projection near the answer (the previous step's) is not needed.

        The polyline's search is exhaustive and exact, and cheap at the testbed's sizes (a few robots, hundreds
        of samples); this is the interface of the exact tube's warm start
        (:meth:`~vtube_planning.geometry.tube.VirtualTube.project_near`), which the swarm step calls.
        """
        return self.project(points_m)

    def half_width_slope(self, l_m: ArrayLike) -> FloatArray:
        """d lambda / dl at arc lengths ``l_m``: the slope of the sample interval holding l (the later one at a
        sample), 0 on the straight extensions, which keep the end widths."""
        l_m = np.asarray(l_m, dtype=float)
        slopes = np.diff(self.half_width_m) / np.diff(self.l_m)
        k = np.clip(np.searchsorted(self.l_m, l_m, side='right') - 1, 0, slopes.size - 1)
        within = (l_m >= self.l_m[0]) & (l_m < self.length_m)
        slope: FloatArray = np.where(within, slopes[k], 0.0)
        return slope

    def area(self, l_m: ArrayLike) -> FloatArray:
        """Cumulative area A(l), m^2; the straight extensions keep the end widths (negative before l = 0)."""
        l_m = np.asarray(l_m, dtype=float)
        inner = np.interp(l_m, self.l_m, self.area_m2)
        before = 2.0 * self.half_width_m[0] * np.minimum(l_m - self.l_m[0], 0.0)
        after = 2.0 * self.half_width_m[-1] * np.maximum(l_m - self.length_m, 0.0)
        area: FloatArray = inner + before + after
        return area
