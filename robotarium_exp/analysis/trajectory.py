"""One trajectory type for every source: frames, positions (T, 2, N), headings, robot ids, coverage, provenance.

Sources differ in rate and completeness: robots start and stop at different times, drop out for seconds, and are
stamped at their own instants. Loaders therefore hand over each robot's own samples
([`RobotSamples`][robotarium_exp.analysis.trajectory.RobotSamples], stamps in integer nanoseconds), and `assemble` puts
them on one clock without resampling the robots' rate: the frames are the robots' stamps, where stamps that fall within
half the shortest sampling period of a frame's first stamp are one frame (`frame_stamps`: a motion-capture system that
stamps each body a few milliseconds apart gives one frame per capture, not one per body, and the frames stay as many as
one robot's samples, or at most twice as many, whatever the number of robots). A robot has a position at a frame when
it has a sample there, or when the frame lies between two of its samples that are at most the largest bridged hole
([`MaxGap`][robotarium_exp.analysis.trajectory.MaxGap]) apart (linear interpolation), or else when one of its samples
falls within the frame's window (its first and last samples, and the ends of gaps); elsewhere its position is NaN.
Nothing is dropped silently: every sample left out (a repeated stamp, a non-finite position) and every frame a robot
misses (before its first sample, after its last, inside a gap) is counted in its `Coverage`.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotarium_exp.errors import AnalysisError

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

_MAX_GAP = re.compile(r'^\s*(?P<value>\d+(?:\.\d*)?|\.\d+)\s*(?P<unit>s|ms|periods?|p)\s*$')


SAMPLING_S = (1e-4, 10.0)
"""The median interval between a robot's samples must lie in this range (s): a tracker or a testbed samples at 0.1 Hz
to 10 kHz; anything else is stamps read in the wrong unit."""
PLAUSIBLE_M = 1.0e6
"""A position coordinate beyond this (m) is no measurement (no arena or motion-capture volume is that large): the
sample is left out and counted with the non-finite ones."""


@dataclass(frozen=True)
class MaxGap:
    """The longest hole between two samples of a robot that is bridged by interpolation; a longer one is a gap.

    Given in seconds or in periods (multiples of the robot's own median sample period), and compared exactly, in
    integer nanoseconds: a hole of exactly the limit is bridged.
    """

    value: Fraction
    unit: str

    @classmethod
    def parse(cls, text: str) -> MaxGap:
        """``'3periods'`` (also ``'3p'``), ``'0.25s'`` or ``'250ms'``."""
        match = _MAX_GAP.match(text)
        if not match:
            msg = f"max gap {text!r} is not a number with a unit; write e.g. '3periods', '0.25s' or '250ms'."
            raise AnalysisError(msg)
        value, unit = Fraction(match['value']), match['unit']
        if unit == 'ms':
            value, unit = value / 1000, 's'
        return cls(value, 's' if unit == 's' else 'periods')

    def limit_ns(self, period_ns: Fraction) -> int:
        """The longest bridged hole in nanoseconds, for a robot whose median period is ``period_ns``."""
        scale = period_ns if self.unit == 'periods' else Fraction(1_000_000_000)
        return math.floor(self.value * scale)

    def __str__(self) -> str:
        return f'{float(self.value):g}{"s" if self.unit == "s" else "periods"}'


DEFAULT_MAX_GAP = MaxGap(Fraction(3), 'periods')


@dataclass(frozen=True)
class RobotSamples:
    """One robot's samples as recorded: stamps (k,) in integer nanoseconds (any order, repeats allowed), positions
    (k, 2), headings (k,) or None."""

    stamps_ns: IntArray
    xy_m: FloatArray
    heading_rad: FloatArray | None = None


@dataclass(frozen=True)
class Gap:
    """A hole longer than the bridged limit in one robot's samples: the samples before and after it, in seconds."""

    robot: str
    start_s: float
    end_s: float


@dataclass(frozen=True)
class Coverage:
    """What one robot contributes to a trajectory.

    Attributes
    ----------
    samples
        Samples used.
    first_s, last_s
        Its first and last sample (NaN without any).
    frames
        Frames at which it has a position.
    before_first, after_last, in_gaps
        Frames at which it has none, by reason.
    repeated_stamps, non_finite
        Samples left out: a second sample at a stamp already seen, a position that is NaN, infinite or beyond
        PLAUSIBLE_M.
    max_gap_s
        The longest hole bridged for this robot.
    """

    robot: str
    samples: int
    first_s: float
    last_s: float
    frames: int
    before_first: int
    after_last: int
    in_gaps: int
    repeated_stamps: int
    non_finite: int
    max_gap_s: float


@dataclass(frozen=True)
class Trajectory:
    """Robot positions over time.

    Attributes
    ----------
    t_s
        Time of each frame in seconds from the first one, (T,), increasing.
    positions_m
        Positions, (T, 2, N); NaN where a robot has no position (see ``coverage``).
    headings_rad
        Headings, (T, N), when the source has them.
    robot_ids
        One name per robot (column).
    source
        Where it came from: kind, paths, the files read, what was ignored and why.
    gaps
        Holes longer than the bridged limit, never interpolated across.
    coverage
        Per robot: samples used and left out, frames with and without a position.
    """

    t_s: FloatArray
    positions_m: FloatArray
    headings_rad: FloatArray | None
    robot_ids: tuple[str, ...]
    source: dict[str, Any] = field(default_factory=dict)
    gaps: tuple[Gap, ...] = ()
    coverage: tuple[Coverage, ...] = ()

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
        if not np.all(np.isfinite(t)):
            msg = 'time stamps must be finite.'
            raise AnalysisError(msg)
        if np.any(np.diff(t) <= 0):
            msg = f'time stamps must increase; {self.source.get("path", "?")} has repeated or decreasing stamps.'
            raise AnalysisError(msg)

    @property
    def n_robots(self) -> int:
        return len(self.robot_ids)

    def present(self) -> NDArray[np.bool_]:
        """Whether each robot has a position at each frame, (T, N)."""
        present: NDArray[np.bool_] = np.all(np.isfinite(self.positions_m), axis=1)
        return present

    def complete_frames(self) -> NDArray[np.bool_]:
        """Frames at which every robot has a position, (T,)."""
        complete: NDArray[np.bool_] = np.all(self.present(), axis=1)
        return complete

    def common_span(self) -> tuple[float, float]:
        """From the latest first position to the earliest last one over the robots that have any (s): the time
        every such robot is recorded; the whole recording when there is no such time (one robot stops before
        another starts)."""
        present = self.present()
        seen = present.any(axis=0)
        if not seen.any():
            return float(self.t_s[0]), float(self.t_s[-1])
        first = self.t_s[np.argmax(present[:, seen], axis=0)]
        last = self.t_s[self.t_s.size - 1 - np.argmax(present[::-1, seen], axis=0)]
        start, end = float(first.max()), float(last.min())
        return (start, end) if start <= end else (float(self.t_s[0]), float(self.t_s[-1]))

    def positions_at(self, t_s: float) -> FloatArray:
        """Every robot's position at time ``t_s``, (2, N): its position at a frame at that time, else interpolated
        between its positions at the two frames around it when those are consecutive frames (no gap between), else
        its position at a frame within the source's frame window (``frame_window_s``) of it; NaN otherwise."""
        window = float(self.source.get('frame_window_s', 0.0))
        out = np.full((2, self.n_robots), np.nan)
        for k, frames in enumerate(self.present().T):
            index = np.flatnonzero(frames)
            if not index.size:
                continue
            times = self.t_s[index]
            j = int(np.searchsorted(times, t_s, side='right')) - 1
            if j >= 0 and (times[j] == t_s or (j + 1 < index.size and index[j + 1] == index[j] + 1)):
                step = 0.0 if times[j] == t_s else (t_s - times[j]) / (times[j + 1] - times[j])
                after = self.positions_m[index[min(j + 1, index.size - 1)], :, k]
                out[:, k] = self.positions_m[index[j], :, k] + step * (after - self.positions_m[index[j], :, k])
                continue
            near = int(np.argmin(np.abs(times - t_s)))
            if abs(float(times[near]) - t_s) <= window:
                out[:, k] = self.positions_m[index[near], :, k]
        return out


def check_time(rid: str, stamps: IntArray) -> None:
    """Refuse a robot's stamps that are not a recording's time, rather than re-sort or merge them into wrong
    frames: stamps that go back (a clock that jumped, or samples out of order), all one stamp, or an interval
    between samples outside SAMPLING_S (stamps in another unit than the loader read them in)."""
    if stamps.size < 2:
        return
    step = np.diff(stamps)
    if np.any(step < 0):
        k = int(np.argmin(step))
        msg = (
            f'robot {rid!r}: its time stamps go back by up to {-step[k] * 1e-9:.3f} s ({int((step < 0).sum())} of '
            f'{step.size} steps, the largest at sample {k + 1}): the clock jumped or the samples are out of order, and '
            're-sorting them would pair positions of different moments; analyse the parts before and after separately.'
        )
        raise AnalysisError(msg)
    interval_s = float(np.median(step[step > 0])) * 1e-9 if np.any(step > 0) else 0.0
    if interval_s == 0.0:
        msg = f'robot {rid!r}: all {stamps.size} samples have the same time stamp: the recording holds no time.'
        raise AnalysisError(msg)
    if not SAMPLING_S[0] <= interval_s <= SAMPLING_S[1]:
        msg = (
            f'robot {rid!r}: its samples are {interval_s:.3g} s apart (median), outside {SAMPLING_S[0]:g}-'
            f'{SAMPLING_S[1]:g} s: the stamps are in another unit than seconds (milliseconds, nanoseconds?); '
            'convert them to seconds.'
        )
        raise AnalysisError(msg)


def seconds_to_ns(t_s: ArrayLike, where: str = 'the time stamps') -> IntArray:
    """Stamps in seconds (a file's float array) as integer nanoseconds, rounded to the nanosecond; refused, naming
    the first and ``where`` they come from, when some are NaN, infinite or beyond what nanoseconds hold (292 years)."""
    seconds = np.asarray(t_s, dtype=float)
    bad = ~(np.abs(seconds) < 9.2e9)  # NaN, infinite or out of int64's range in nanoseconds
    if bad.any():
        k = int(np.flatnonzero(bad.ravel())[0])
        msg = (
            f'{where} hold {int(bad.sum())} value(s) that are not a time (the first, {float(seconds.ravel()[k])}, at row '
            f'{k}); every stamp must be a finite number of seconds: repair or cut those rows.'
        )
        raise AnalysisError(msg)
    return np.round(seconds * 1e9).astype(np.int64)


def _clean(rid: str, samples: RobotSamples) -> tuple[IntArray, FloatArray, FloatArray | None, int, int]:
    """The samples, in time (`check_time`), with non-finite or implausible positions and repeated stamps left
    out (and counted); copied only when something is left out."""
    stamps = np.asarray(samples.stamps_ns, dtype=np.int64)
    xy = np.asarray(samples.xy_m, dtype=float).reshape(-1, 2)
    heading = None if samples.heading_rad is None else np.asarray(samples.heading_rad, dtype=float)
    if stamps.ndim != 1 or xy.shape[0] != stamps.size or (heading is not None and heading.shape != stamps.shape):
        msg = f'robot {rid!r}: {stamps.size} stamps but positions {xy.shape} and headings of another length.'
        raise AnalysisError(msg)
    check_time(rid, stamps)
    non_finite = repeated = 0
    for keep in (np.all(np.abs(xy) <= PLAUSIBLE_M, axis=1), None):  # False for NaN too; then repeated stamps
        if keep is None:
            keep = np.concatenate([[True], np.diff(stamps) > 0])[: stamps.size]  # (none left: empty)
            repeated = int(stamps.size - np.count_nonzero(keep))
        else:
            non_finite = int(stamps.size - np.count_nonzero(keep))
        if not keep.all():
            stamps, xy = stamps[keep], xy[keep]
            heading = None if heading is None else heading[keep]
    return stamps, xy, heading, repeated, non_finite


def frame_stamps(stamps: list[IntArray]) -> tuple[IntArray, int]:
    """The frames of robots sampled at ``stamps`` (each sorted, without repeats) and the window that joins stamps.

    The window is half the shortest median sampling period of a robot. Going through the stamps in time, a frame
    starts at the first stamp not yet in one and takes every stamp less than the window after it; the frame's time
    is that first stamp. Robots sampled together keep one frame per stamp; a robot appears at most once in a frame
    (its samples are further apart than the window, but for rare jitter).
    """
    every = np.concatenate(stamps)
    every.sort()
    every = every[np.concatenate([[True], every[1:] != every[:-1]])]  # (not np.unique: its hash table is larger)
    periods = [int(np.median(np.diff(s))) for s in stamps if s.size > 1]
    window = min(periods) // 2 if periods else 0
    if every.size < 2 or int(np.diff(every).min()) >= window:
        return every, window  # (the common case: robots sampled together) every stamp its own frame
    following = np.searchsorted(every, every + window, side='left')  # the first stamp outside each one's window
    starts, k = [], 0
    while k < every.size:  # one step per frame
        starts.append(k)
        k = int(following[k])
    return every[np.asarray(starts, dtype=np.int64)], window


def _taken_as_is(frames_ns: IntArray, stamps: IntArray, ok: NDArray[np.bool_]) -> tuple[IntArray, IntArray]:
    """The frames without a position at their time in which a robot has a sample, and that sample (its first in
    the frame), which is taken as it is: its first and last samples, the ends of its gaps."""
    frame_of = np.searchsorted(frames_ns, stamps, side='right') - 1  # the frame each sample falls in
    first_in = np.flatnonzero(np.concatenate([[True], np.diff(frame_of) > 0]))
    taken = first_in[~ok[frame_of[first_in]]]
    return frame_of[taken], taken


def assemble(
    samples: dict[str, RobotSamples], *, source: dict[str, Any], max_gap: MaxGap = DEFAULT_MAX_GAP
) -> Trajectory:
    """Robots sampled at their own stamps -> one `Trajectory` on the frames of their stamps (module doc)."""
    if not samples:
        msg = f'no robot data found in {source.get("path", "?")}; check the topic or frame pattern.'
        raise AnalysisError(msg)
    ids = tuple(sorted(samples))
    cleaned = {rid: _clean(rid, samples[rid]) for rid in ids}
    used = [c[0] for c in cleaned.values() if c[0].size]
    if not used:
        msg = f'no robot in {source.get("path", "?")} has a finite position.'
        raise AnalysisError(msg)
    frames_ns, window = frame_stamps(used)
    origin = int(frames_ns[0])
    seconds = np.asarray((frames_ns - origin) * 1e-9, dtype=np.float64)  # the one conversion to seconds
    positions = np.full((frames_ns.size, 2, len(ids)), np.nan)
    with_headings = all(c[2] is not None for c in cleaned.values())
    headings = np.full((frames_ns.size, len(ids)), np.nan) if with_headings else None
    gaps, coverage = [], []
    for k, rid in enumerate(ids):
        stamps, xy, heading, repeated, non_finite = cleaned[rid]
        if not stamps.size:  # every sample left out: no position anywhere
            nothing = Coverage(rid, 0, math.nan, math.nan, 0, frames_ns.size, 0, 0, repeated, non_finite, math.nan)
            coverage.append(nothing)
            continue
        steps = np.diff(stamps)
        limit = max_gap.limit_ns(Fraction(float(np.median(steps))) if steps.size else Fraction(0))
        left = np.searchsorted(stamps, frames_ns, side='right') - 1  # last sample at or before each frame
        at, nxt = np.clip(left, 0, stamps.size - 1), np.clip(left + 1, 0, stamps.size - 1)
        before = left < 0
        exact = ~before & (stamps[at] == frames_ns)
        between = ~before & ~exact & (left < stamps.size - 1)
        span = stamps[nxt] - stamps[at]
        bridged = between & (span <= limit)
        ok = exact | bridged
        weight = np.where(bridged, (frames_ns - stamps[at]) / np.where(span > 0, span, 1), 0.0)
        positions[ok, :, k] = (xy[at] + weight[:, None] * (xy[nxt] - xy[at]))[ok]
        frames, taken = _taken_as_is(frames_ns, stamps, ok)
        positions[frames, :, k] = xy[taken]
        if headings is not None and heading is not None:
            turn = np.angle(np.exp(1j * (heading[nxt] - heading[at])))
            headings[ok, k] = np.angle(np.exp(1j * (heading[at] + weight * turn)))[ok]
            headings[frames, k] = heading[taken]
        for j in np.flatnonzero(steps > limit):
            gaps.append(Gap(rid, (int(stamps[j]) - origin) * 1e-9, (int(stamps[j + 1]) - origin) * 1e-9))
        snapped = np.zeros(frames_ns.size, dtype=bool)
        snapped[frames] = True
        missed = (before & ~snapped, ~before & ~exact & ~between & ~snapped, between & ~bridged & ~snapped)
        first_s, last_s = ((int(stamps[j]) - origin) * 1e-9 for j in (0, -1))
        frames_with = int((ok | snapped).sum())
        early, late, in_gaps = (int(m.sum()) for m in missed)
        used_n = int(stamps.size)
        coverage.append(
            Coverage(
                rid, used_n, first_s, last_s, frames_with, early, late, in_gaps, repeated, non_finite, limit * 1e-9
            )
        )
    source = {**source, 'frame_window_s': window * 1e-9}
    return Trajectory(seconds, positions, headings, ids, source, tuple(gaps), tuple(coverage))
