"""The certificate of a warm-started projection
([`project_near`][vtube_planning.geometry.tube.VirtualTube.project_near]): per sample of the tube, the bounds that
prove a local Newton answer is the closest point of the whole curve."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import maximum_filter1d
from scipy.spatial import cKDTree

from vtube_planning.geometry.centerline import CenterCurve
from vtube_planning.geometry.regularity import check_grid
from vtube_planning.geometry.width import WidthProfile

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class WarmTable:
    """Per sample s_i of the tube's sample grid, what `VirtualTube.project_near` certifies a local answer with.

    Attributes
    ----------
    l_m, points
        The samples s_i (K,) and gamma(s_i) (K, 2).
    window_m
        W = 2 lambda_max + 3 h, h the largest gap between samples: a point at the wall of a straight part has
        q + d of about 2 lambda_max + h/2 against T_i of about W - h/2 there, so it certifies.
    far_m
        T_i (K,): a lower bound of |gamma(s_i) - gamma(l')| over all l' with |l' - s_i| >= W, the straight extensions
        beyond both ends included: the exact distance to the far parts of the two rays, and for the curve between
        samples the distance to the nearest sample s_j with |s_j - s_i| >= W - h/2 less h/2 (every curve point is
        within h/2 of arc, hence of distance, of such a sample). inf where no such part exists.
    kappa_max
        K_i (K,): the largest |kappa| on the regularity check grid (4x finer than the samples, every breakpoint
        included) within W + h of s_i (with whole sample intervals), zero beyond the ends. Exact for an
        [`ArcPath`][vtube_planning.geometry.centerline.ArcPath] (curvature constant between breakpoints); for a
        spline as fine as the regularity checks themselves.
    """

    l_m: FloatArray
    points: FloatArray
    window_m: float
    far_m: FloatArray
    kappa_max: FloatArray

    @classmethod
    def of(cls, center: CenterCurve, width: WidthProfile, samples: FloatArray, tree: cKDTree) -> WarmTable:
        """The table of a tube (centre curve, width), its sample arc lengths and the k-d tree of their points."""
        points, tangents, _ = center.frame(samples)
        length, size = center.length_m, samples.size
        gap = float(np.diff(samples).max())
        grid = check_grid(center, width, samples)
        window = 2.0 * float(width.value(grid).max()) + 3.0 * gap
        reach = window - 0.5 * gap  # samples this far (in arc length) or farther bound the far curve
        near = np.searchsorted(samples, samples + reach, 'left') - np.searchsorted(samples, samples - reach, 'right')
        k = min(size, int(near.max()) + 1)  # the nearest far sample is among the k nearest samples
        far = np.empty(size)
        for start in range(0, size, 4096):
            rows = slice(start, min(size, start + 4096))
            dist, idx = tree.query(points[rows], k=k)
            dist, idx = dist.reshape(-1, k), idx.reshape(-1, k)
            outside = np.abs(samples[idx] - samples[rows, None]) >= reach
            far[rows] = np.where(outside, dist, np.inf).min(axis=1) - 0.5 * gap
        back = ray_distance(points, points[0], -tangents[0], np.maximum(0.0, window - samples))
        ahead = ray_distance(points, points[-1], tangents[-1], np.maximum(0.0, samples + window - length))
        far = np.minimum(far, np.minimum(back, ahead))
        # largest |kappa| per sample interval, then over every interval within W + h of each sample (a superset)
        kappa = np.abs(center.frame(grid)[2])
        starts = np.searchsorted(grid, samples[:-1])
        per_interval = np.maximum(np.maximum.reduceat(kappa, starts), kappa[np.searchsorted(grid, samples[1:])])
        lo = np.searchsorted(samples, samples - window - gap, 'right') - 1
        hi = np.searchsorted(samples, samples + window + gap, 'left')
        span = int(np.max(np.maximum(np.arange(size) - lo, hi - np.arange(size))))
        padded = np.append(per_interval, per_interval[-1])  # interval i starts at sample i; the last sample's own
        kappa_max = maximum_filter1d(padded, size=2 * span + 1, mode='nearest')
        return cls(samples, points, window, far, kappa_max)

    def nearest_sample(self, l_m: FloatArray) -> NDArray[np.intp]:
        """Index of a sample nearest to each arc length (the first or the last beyond the ends). Near a midpoint
        between two samples either may come out: the certificate holds with any sample whose window contains l,
        which `VirtualTube.project_near` checks."""
        return self._midpoints.searchsorted(l_m, side='right')

    @cached_property
    def _midpoints(self) -> FloatArray:
        return 0.5 * (self.l_m[:-1] + self.l_m[1:])

    @cached_property
    def x_m(self) -> FloatArray:
        """The x of gamma(s_i), contiguous (gathered from it, not from ``points``' column)."""
        x: FloatArray = self.points[:, 0].copy()
        return x

    @cached_property
    def y_m(self) -> FloatArray:
        """The y of gamma(s_i), contiguous."""
        y: FloatArray = self.points[:, 1].copy()
        return y


def ray_distance(points: FloatArray, base: FloatArray, direction: FloatArray, start: FloatArray) -> FloatArray:
    """Distance from each of (K, 2) points to its ray {base + u direction : u >= start} (unit direction)."""
    u = np.maximum((points - base) @ direction, start)
    foot = base + u[:, None] * direction
    return np.hypot(points[:, 0] - foot[:, 0], points[:, 1] - foot[:, 1])
