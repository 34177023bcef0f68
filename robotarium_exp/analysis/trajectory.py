"""One trajectory type for every source: time stamps, positions (T, 2, N), headings, robot ids, provenance.

Sources differ in rate and completeness. :func:`on_common_stamps` puts robots sampled at different times onto
one clock by linear interpolation, but never across a gap: samples inside a gap (more than ``gap_factor`` median
periods without data) stay NaN and the gap is reported in ``Trajectory.gaps``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.errors import AnalysisError

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Gap:
    """A stretch without samples of one robot, in seconds."""

    robot: str
    start_s: float
    end_s: float


@dataclass(frozen=True)
class Trajectory:
    """Robot positions over time.

    Attributes
    ----------
    t_s
        Time stamps in seconds from the first sample, (T,), increasing.
    positions_m
        Positions, (T, 2, N); NaN where a robot has no data (inside a reported gap).
    headings_rad
        Headings, (T, N), when the source has them.
    robot_ids
        One name per robot (column).
    source
        Where it came from: kind, path, topic names, anything the loader knows.
    gaps
        Stretches without data.
    """

    t_s: FloatArray
    positions_m: FloatArray
    headings_rad: FloatArray | None
    robot_ids: tuple[str, ...]
    source: dict[str, Any] = field(default_factory=dict)
    gaps: tuple[Gap, ...] = ()

    def __post_init__(self) -> None:
        t, p = np.asarray(self.t_s), np.asarray(self.positions_m)
        if t.ndim != 1 or p.ndim != 3 or p.shape[0] != t.size or p.shape[1] != 2 or p.shape[2] != len(self.robot_ids):
            msg = (
                f'a trajectory needs t (T,), positions (T, 2, N) and N robot ids; got {t.shape}, {p.shape}, '
                f'{len(self.robot_ids)} ids.'
            )
            raise AnalysisError(msg)
        if t.size == 0:
            msg = f'the trajectory from {self.source.get("path", "?")} has no samples.'
            raise AnalysisError(msg)
        if np.any(np.diff(t) <= 0):
            msg = f'time stamps must increase; {self.source.get("path", "?")} has repeated or decreasing stamps.'
            raise AnalysisError(msg)
        if not np.all(np.isfinite(t)):
            msg = 'time stamps must be finite.'
            raise AnalysisError(msg)

    @property
    def n_robots(self) -> int:
        return len(self.robot_ids)

    def complete_frames(self) -> NDArray[np.bool_]:
        """Steps at which every robot has a position, (T,)."""
        return np.all(np.isfinite(self.positions_m), axis=(1, 2))


def on_common_stamps(
    samples: dict[str, tuple[FloatArray, FloatArray, FloatArray | None]],
    *,
    source: dict[str, Any],
    rate_hz: float | None = None,
    gap_factor: float = 3.0,
) -> Trajectory:
    """Robots sampled at their own stamps -> one Trajectory on common stamps.

    Parameters
    ----------
    samples
        Per robot id: stamps in seconds (k,), positions (k, 2), headings (k,) or None.
    rate_hz
        Rate of the common stamps; defaults to the fastest robot's median rate.
    gap_factor
        A stretch longer than this many median periods without a sample is a gap.
    """
    if not samples:
        msg = f'no robot data found in {source.get("path", "?")}; check the topic or frame pattern.'
        raise AnalysisError(msg)
    ids = tuple(sorted(samples))
    periods = []
    for rid in ids:
        stamps = samples[rid][0]
        if stamps.size < 2:
            msg = f'robot {rid!r} has {stamps.size} sample(s) in {source.get("path", "?")}; at least 2 are needed.'
            raise AnalysisError(msg)
        periods.append(float(np.median(np.diff(stamps))))
    period = 1.0 / rate_hz if rate_hz else min(periods)
    start = max(samples[rid][0][0] for rid in ids)
    stop = min(samples[rid][0][-1] for rid in ids)
    if stop <= start:
        msg = f'the robots in {source.get("path", "?")} have no time span in common.'
        raise AnalysisError(msg)
    shared = samples[ids[0]][0]
    if all(samples[rid][0].shape == shared.shape and np.array_equal(samples[rid][0], shared) for rid in ids):
        t = shared  # every robot sampled at the same instants: nothing to resample
    else:
        t = np.arange(start, stop + 0.5 * period, period)
        t = t[t <= stop]
    positions = np.full((t.size, 2, len(ids)), np.nan)
    headings = np.full((t.size, len(ids)), np.nan) if all(samples[r][2] is not None for r in ids) else None
    gaps = []
    for k, (rid, own_period) in enumerate(zip(ids, periods, strict=True)):
        stamps, xy, theta = samples[rid]
        if not np.all(np.isfinite(xy)):
            bad = int(np.argmax(~np.all(np.isfinite(xy), axis=1)))
            msg = f'robot {rid!r} has a NaN or inf position at t = {stamps[bad]:.3f} s in {source.get("path", "?")}.'
            raise AnalysisError(msg)
        positions[:, 0, k] = np.interp(t, stamps, xy[:, 0])
        positions[:, 1, k] = np.interp(t, stamps, xy[:, 1])
        if headings is not None and theta is not None:
            headings[:, k] = np.arctan2(np.interp(t, stamps, np.sin(theta)), np.interp(t, stamps, np.cos(theta)))
        jumps = np.flatnonzero(np.diff(stamps) > gap_factor * own_period)
        for j in jumps:
            gaps.append(Gap(rid, float(stamps[j] - start), float(stamps[j + 1] - start)))
            inside = (t > stamps[j]) & (t < stamps[j + 1])
            positions[inside, :, k] = np.nan
            if headings is not None:
                headings[inside, k] = np.nan
    return Trajectory(t - start, positions, headings, ids, source, tuple(gaps))
