"""The obstacles as arrays, their exact clearance, and the obstacles that may be nearest to a block of points.

`Shapes` holds discs (centres, radii) and polygons (their edges, one array for all, and bounding boxes).
`Shapes.clearance` is the exact distance to the nearest of them, 0 inside one (even-odd rule).
`Shapes.near` keeps only what may be nearest to a block of points and drops the rest exactly, not by an
estimate: every point of the block's bounding box is at most ``reach`` from some obstacle (a disc's or a vertex's
distance from the box's farthest corner), so an obstacle whose bounding box lies farther than ``reach`` from the
block's box is nearer to none of its points, and the clearance over what is kept is the clearance over all,
to the bit. A relative slack of 1e-9 keeps the few obstacles whose distances round within it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

CHUNK = 4096
"""Points per chunk in the clearance (bounds the (points x edges) arrays)."""
SLACK = 1e-9
"""Relative slack of `Shapes.near` (far above the rounding of the distances it compares)."""


@dataclass(frozen=True, eq=False)
class Shapes:
    """Discs and polygons as arrays: ``centers`` (c, 2), ``radii`` (c,); every polygon's edges, starts ``a``
    (e, 2) and directions ``d`` (e, 2), ``owner`` (e,) the polygon of each, ``counts`` (p,) its edges, and the
    polygons' bounding boxes ``low``, ``high`` (p, 2)."""

    centers: FloatArray
    radii: FloatArray
    a: FloatArray
    d: FloatArray
    owner: NDArray[np.intp]
    counts: NDArray[np.intp]
    low: FloatArray
    high: FloatArray

    @classmethod
    def of(cls, discs: list[tuple[tuple[float, float], float]], polygons: list[FloatArray]) -> Shapes:
        """The arrays of discs (centre, radius) and polygons (vertices (k, 2), closed implicitly)."""
        centers = np.array([c for c, _ in discs], dtype=float).reshape(-1, 2)
        radii = np.array([r for _, r in discs], dtype=float)
        a = np.vstack([*polygons, np.empty((0, 2))])
        d = np.vstack([*(np.roll(xy, -1, axis=0) - xy for xy in polygons), np.empty((0, 2))])
        counts = np.array([len(xy) for xy in polygons], dtype=np.intp)
        owner = np.repeat(np.arange(len(polygons), dtype=np.intp), counts)
        low = np.array([xy.min(axis=0) for xy in polygons]).reshape(-1, 2)
        high = np.array([xy.max(axis=0) for xy in polygons]).reshape(-1, 2)
        return cls(centers, radii, a, d, owner, counts, low, high)

    def polygon(self, k: int) -> Shapes:
        """The ``k``-th polygon alone."""
        return self._subset(np.zeros(self.radii.size, dtype=bool), np.arange(self.counts.size) == k)

    def near(self, p: FloatArray) -> Shapes:
        """What may be nearest to some of the (k, 2) points ``p`` (module doc); all of it for points not finite."""
        low, high = p.min(axis=0), p.max(axis=0)
        far_discs = np.hypot(*np.maximum(np.abs(self.centers - low), np.abs(self.centers - high)).T) - self.radii
        far_vertices = np.hypot(*np.maximum(np.abs(self.a - low), np.abs(self.a - high)).T)
        reach = min(far_discs.min(initial=np.inf), far_vertices.min(initial=np.inf))
        limit = reach + SLACK * (1.0 + reach + float(np.abs(p).max()))
        if not np.isfinite(limit):
            return self
        to_discs = np.hypot(*np.maximum(np.maximum(self.centers - high, low - self.centers), 0.0).T) - self.radii
        to_polygons = np.hypot(*np.maximum(np.maximum(self.low - high, low - self.high), 0.0).T)
        return self._subset(to_discs <= limit, to_polygons <= limit)

    def _subset(self, discs: NDArray[np.bool_], polygons: NDArray[np.bool_]) -> Shapes:
        edges, counts = polygons[self.owner], self.counts[polygons]
        return Shapes(
            self.centers[discs],
            self.radii[discs],
            self.a[edges],
            self.d[edges],
            np.repeat(np.arange(counts.size, dtype=np.intp), counts),
            counts,
            self.low[polygons],
            self.high[polygons],
        )

    def clearance(self, points: FloatArray) -> FloatArray:
        """Distance (k,) of (k, 2) points to the nearest disc or polygon, 0 on or inside one; inf without any."""
        out = np.full(points.shape[0], np.inf)
        for start in range(0, points.shape[0], CHUNK):
            out[start : start + CHUNK] = self._clearance_chunk(points[start : start + CHUNK])
        return out

    def _clearance_chunk(self, p: FloatArray) -> FloatArray:
        best = np.full(p.shape[0], np.inf)
        if self.radii.size:
            centers, radii = self.centers, self.radii
            gaps = np.hypot(p[:, None, 0] - centers[None, :, 0], p[:, None, 1] - centers[None, :, 1]) - radii
            best = np.minimum(best, np.maximum(gaps.min(axis=1), 0.0))
        if self.counts.size:
            a, d = self.a, self.d
            starts = np.concatenate([[0], np.cumsum(self.counts)[:-1]]).astype(np.intp)
            rel = p[:, None, :] - a[None, :, :]  # (k, e, 2)
            t = np.clip((rel * d).sum(axis=2) / (d * d).sum(axis=1), 0.0, 1.0)
            gaps = np.hypot(*(rel - t[:, :, None] * d).transpose(2, 0, 1))  # (k, e)
            upward = (a[None, :, 1] <= p[:, None, 1]) != (a[None, :, 1] + d[None, :, 1] <= p[:, None, 1])
            with np.errstate(divide='ignore', invalid='ignore'):
                x_cross = a[:, 0] + (p[:, None, 1] - a[:, 1]) * d[:, 0] / d[:, 1]
            crossings = np.add.reduceat((upward & (p[:, None, 0] < x_cross)).astype(np.int64), starts, axis=1)
            nearest = np.minimum.reduceat(gaps, starts, axis=1)  # (k, polygons)
            best = np.minimum(best, np.where(crossings % 2 == 1, 0.0, nearest).min(axis=1))
        return best
