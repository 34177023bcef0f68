"""Distances between robots over each pair's own common coverage, from a trajectory with holes.

A pair is measured at the frames where both robots have a position (`Trajectory.present`): a robot whose log
ends early, or that drops out, leaves the other pairs measured over their whole time, and no distance is ever taken
from an interpolation across a gap. The global minimum is the smallest over all pairs and frames. Computed with
numpy over pairs and frames in blocks, so that memory stays bounded for large swarms.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

BLOCK_ELEMENTS = 2_000_000
"""Frame-pair distances held in memory at once."""


@dataclass(frozen=True)
class PairDistances:
    """Distances of every pair (i < j) of robots.

    Attributes
    ----------
    first, second
        The pairs' robot indices, (P,).
    common_frames
        Frames at which both robots have a position, (P,).
    min_m, min_frame
        Each pair's smallest distance over its common frames and the frame index (NaN and -1 without any), (P,).
    below
        Frames at which the pair is closer than the radius, (P,) (zeros without a radius).
    frame_min_m
        Smallest distance over the pairs measured at each frame, (T,) (NaN where no pair is).
    frames_below
        Frames with at least one pair closer than the radius.
    """

    first: IntArray
    second: IntArray
    common_frames: IntArray
    min_m: FloatArray
    min_frame: IntArray
    below: IntArray
    frame_min_m: FloatArray
    frames_below: int


def pair_distances(positions_m: FloatArray, radius_m: float | None = None) -> PairDistances:
    """Distances of all pairs of the (T, 2, N) positions (NaN: no position), and closeness below ``radius_m``."""
    steps, _, n = positions_m.shape
    first, second = (a.astype(np.int64) for a in np.triu_indices(n, k=1))
    pairs = first.size
    common = np.zeros(pairs, dtype=np.int64)
    best = np.full(pairs, np.inf)
    best_frame = np.full(pairs, -1, dtype=np.int64)
    below = np.zeros(pairs, dtype=np.int64)
    frame_min = np.full(steps, np.inf)
    frames_below = 0
    block = max(1, BLOCK_ELEMENTS // max(pairs, 1))
    for start in range(0, steps if pairs else 0, block):
        p = positions_m[start : start + block]
        d = np.hypot(p[:, 0, first] - p[:, 0, second], p[:, 1, first] - p[:, 1, second])  # (t, P), NaN: absent
        measured = ~np.isnan(d)
        d = np.where(measured, d, np.inf)
        common += measured.sum(axis=0)
        k = np.argmin(d, axis=0)
        value = d[k, np.arange(pairs)]
        better = value < best
        best[better], best_frame[better] = value[better], k[better] + start
        frame_min[start : start + block] = d.min(axis=1)
        if radius_m is not None:
            close = d < radius_m
            below += close.sum(axis=0)
            frames_below += int(close.any(axis=1).sum())
    return PairDistances(
        first,
        second,
        common,
        np.where(np.isfinite(best), best, np.nan),
        best_frame,
        below,
        np.where(np.isfinite(frame_min), frame_min, np.nan),
        frames_below,
    )
