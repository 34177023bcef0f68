"""Assembling samples into a trajectory: frames, gaps in integer nanoseconds, MaxGap."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.errors import AnalysisError


def test_gaps_in_integer_nanoseconds_and_max_gap() -> None:
    from fractions import Fraction

    from robotarium_exp.analysis.trajectory import MaxGap, RobotSamples, assemble

    period = 10_000_000  # 0.01 s
    stamps = np.arange(100, dtype=np.int64) * period
    keep = (stamps < 30 * period) | (stamps >= 32 * period)  # a hole of exactly 3 periods: bridged
    keep &= (stamps < 60 * period) | (stamps > 64 * period)  # a hole of 6 periods: a gap
    xy = np.stack([stamps * 1e-9, stamps * 2e-9], axis=1)
    samples = {'a': RobotSamples(stamps, xy), 'b': RobotSamples(stamps[keep], xy[keep])}
    traj = assemble(samples, source={'path': 'x'})
    assert [(g.robot, round(g.start_s, 9), round(g.end_s, 9)) for g in traj.gaps] == [('b', 0.59, 0.65)]
    np.testing.assert_allclose(traj.positions_m[30:32, :, 1], xy[30:32])  # robot a sets the frames; b on a line
    assert np.isnan(traj.positions_m[60:65, 0, 1]).all() and np.isfinite(traj.positions_m[[59, 65], 0, 1]).all()
    b = traj.coverage[1]
    assert (b.samples, b.frames, b.in_gaps, b.before_first, b.after_last) == (93, 95, 5, 0, 0)
    assert MaxGap.parse('250ms') == MaxGap(Fraction(1, 4), 's') and str(MaxGap.parse('2p')) == '2periods'
    strict = assemble(samples, source={'path': 'x'}, max_gap=MaxGap.parse('0.029s'))
    assert len(strict.gaps) == 2
    with pytest.raises(AnalysisError, match="'3' is not a number with a unit"):
        MaxGap.parse('3')


def test_stamps_that_are_no_recordings_time_are_refused_not_resorted() -> None:
    """A clock that jumps back 5 s (two robots 0.4 m apart throughout: re-sorting would pair positions of other
    moments), one stamp for every sample, stamps in milliseconds read as seconds: each refused, naming it."""
    from robotarium_exp.analysis.trajectory import RobotSamples, assemble

    period = 10_000_000  # 0.01 s
    stamps = np.arange(2000, dtype=np.int64) * period
    jumped = np.where(np.arange(2000) < 1000, stamps, stamps - 5_000_000_000)  # back by 5 s half-way
    moving = np.stack([np.linspace(0.0, 10.0, 2000), np.zeros(2000)], axis=1)
    aside = moving + [0.0, 0.4]
    assemble({'a': RobotSamples(stamps, moving), 'b': RobotSamples(stamps, aside)}, source={})  # in time: fine
    cases = (
        (
            jumped,
            r"robot 'a': its time stamps go back by up to 4.990 s \(1 of 1999 steps, the largest at sample 1000\)",
        ),
        (np.zeros(2000, dtype=np.int64), "robot 'a': all 2000 samples have the same time stamp"),
        (stamps * 2000, r"robot 'a': its samples are 20 s apart \(median\), outside 0.0001-10 s"),
        (stamps // 1000, r"robot 'a': its samples are 1e-05 s apart \(median\).*another unit than seconds"),
    )
    for bad, match in cases:
        with pytest.raises(AnalysisError, match=match):
            assemble({'a': RobotSamples(bad, moving), 'b': RobotSamples(stamps, aside)}, source={})


def test_robots_stamped_apart_share_one_frame_per_capture() -> None:
    """Ten bodies stamped 0.4 ms apart at 120 Hz, moving on lines: one frame per capture (not ten), every body at
    every frame, at its true position at the frame's time (interpolated), in the first frame at its first sample."""
    from robotarium_exp.analysis.trajectory import RobotSamples, assemble

    period, steps = 8_333_333, 600
    samples, velocity = {}, np.array([0.3, -0.1])
    for k in range(10):
        stamps = np.arange(steps, dtype=np.int64) * period + k * 400_000
        samples[f'b{k}'] = RobotSamples(stamps, k + stamps[:, None] * 1e-9 * velocity)
    traj = assemble(samples, source={})
    assert traj.positions_m.shape == (steps, 2, 10) and traj.complete_frames().all()
    np.testing.assert_array_equal(np.round(traj.t_s * 1e9), np.arange(steps) * period)  # the first body's stamps
    after = traj.t_s[1:, None, None] * velocity[None, :, None] + np.arange(10)
    np.testing.assert_allclose(traj.positions_m[1:], after, atol=1e-9)  # interpolated at the frame's time
    np.testing.assert_allclose(traj.positions_m[0, :, 9], samples['b9'].xy_m[0])  # its first sample, as it is
    assert all(c.frames == steps and c.samples == steps for c in traj.coverage)
    assert traj.source['frame_window_s'] == pytest.approx(period // 2 * 1e-9)


def test_frames_cover_every_stamp_once_within_the_window() -> None:
    """Random rates, offsets and jitter: every stamp falls in exactly one frame, that begins at a stamp, holds only
    stamps less than the window after its beginning and follows the last one's window; robots sampled together
    on a clock keep every stamp as a frame."""
    from robotarium_exp.analysis.trajectory import frame_stamps

    rng = np.random.default_rng(7)
    for _ in range(40):
        robots = int(rng.integers(1, 12))
        period = int(rng.integers(1_000_000, 100_000_000))
        stamps = [
            np.unique(
                np.cumsum(rng.integers(period // 2, 3 * period // 2, size=int(rng.integers(2, 200))))
                + int(rng.integers(0, 5 * period))
            )
            for _ in range(robots)
        ]
        frames, window = frame_stamps(stamps)
        assert window == min(int(np.median(np.diff(s))) for s in stamps if s.size > 1) // 2
        every = np.unique(np.concatenate(stamps))
        assert np.isin(frames, every).all() and frames[0] == every[0]
        owner = np.searchsorted(frames, every, side='right') - 1
        assert np.all(every - frames[owner] < window)  # inside its frame's window
        assert np.all(np.diff(frames) >= window)  # a frame begins only past the previous one's window
        clock = np.cumsum(rng.integers(3 * period // 4, 5 * period // 4, size=100))  # no interval under half another
        together, _ = frame_stamps([clock, clock.copy()])
        np.testing.assert_array_equal(together, clock)


def test_positions_at_an_instant_interpolate_within_a_robot_s_frames_and_not_across_a_gap() -> None:
    from robotarium_exp.analysis.trajectory import RobotSamples, assemble

    stamps = np.arange(10, dtype=np.int64) * 100_000_000
    t = stamps * 1e-9
    kept = (t < 0.35) | (t > 0.75)  # b has a gap from 0.3 to 0.8 s, longer than three periods
    samples = {
        'a': RobotSamples(stamps + 60_000_000, np.stack([t + 0.06, 0 * t], axis=1)),
        'b': RobotSamples(stamps[kept], np.stack([t, 1 + 0 * t], axis=1)[kept]),
    }
    trajectory = assemble(samples, source={'path': 's'})
    np.testing.assert_allclose(trajectory.common_span(), (0.06, 0.9 - 0.04))  # b's last sample, in the frame at 0.86 s
    np.testing.assert_allclose(trajectory.positions_at(0.125), [[0.125, 0.125], [0.0, 1.0]])
    at = trajectory.positions_at(0.55)  # inside b's gap: a only
    assert at[0, 0] == pytest.approx(0.55) and np.isnan(at[:, 1]).all()
    assert np.isnan(trajectory.positions_at(0.0)[:, 0]).all()  # before a's first sample, further than the frame window


def test_without_a_common_time_the_span_is_the_whole_recording() -> None:
    from robotarium_exp.analysis.trajectory import RobotSamples, assemble

    stamps = np.arange(10, dtype=np.int64) * 100_000_000
    xy = np.zeros((10, 2))
    samples = {'a': RobotSamples(stamps, xy), 'b': RobotSamples(stamps + 2_000_000_000, xy)}  # b starts after a ends
    trajectory = assemble(samples, source={'path': 's'})
    assert trajectory.common_span() == (0.0, pytest.approx(2.9))
    assert np.isnan(trajectory.positions_at(2.5)[:, 0]).all() and np.isfinite(trajectory.positions_at(2.5)[:, 1]).all()
