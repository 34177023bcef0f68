"""The analysis figures, drawn headless from analysed synthetic trajectories."""

from __future__ import annotations

import numpy as np

from robotarium_exp.analysis.plots import SOURCES, analysis_figures
from robotarium_exp.analysis.report import analyse
from robotarium_exp.analysis.trajectory import MaxGap, RobotSamples, assemble


def analysed(scene=None, shift: float = 0.0):
    t = np.arange(300) * 0.1
    x = -1.8 + 0.1 * t[:, None] - np.array([0.0, 0.3, 0.6]) + shift
    y = np.broadcast_to(np.array([-0.2, 0.0, 0.2]), x.shape)
    stamps = np.arange(300, dtype=np.int64) * 100_000_000
    samples = {f'r{k}': RobotSamples(stamps, np.stack([x[:, k], y[:, k]], axis=1)) for k in range(3)}
    return analyse(assemble(samples, source={'path': 'synthetic'}), scene, collision_distance_m=0.25)


def test_figures_with_a_scene_a_plan_and_a_comparison(trapezoid) -> None:
    scene, plan = trapezoid
    results = {'data': analysed(scene), 'comparison': analysed(scene, 0.05)}
    figures = analysis_figures(results, scene, plan)
    assert list(figures) == ['paths', 'tracking', 'distance']
    paths = figures['paths'].axes
    assert paths[0].get_title() == f'data ({SOURCES["data"]}): paths, robots at seven instants'
    assert len(paths[0].collections) >= 7 and paths[-1].get_label() == '<colorbar>'
    ax_v, ax_rho = figures['tracking'].axes
    labels = [line.get_label() for line in ax_v.lines]
    assert len(ax_rho.lines) == 3  # two sources and the plan's density
    assert 'the plan (v*, rho*)' in labels and f'comparison ({SOURCES["comparison"]})' in labels
    (ax,) = figures['distance'].axes
    first = ax.lines[0]
    np.testing.assert_allclose(first.get_ydata(), results['data'].distances.frame_min_m)
    assert any(line.get_label() == 'collision distance' and line.get_ydata()[0] == 0.25 for line in ax.lines)


def test_without_a_scene_no_tracking_figure() -> None:
    figures = analysis_figures({'run': analysed()}, None, None)
    assert list(figures) == ['paths', 'distance'] and figures['paths'].axes[0].get_title().startswith('run: paths')


def test_long_recordings_are_thinned_without_hiding_a_close_approach_or_a_gap(monkeypatch) -> None:
    """Drawn at most DRAWN_FRAMES frames a line: the minimum distance keeps each block's smallest value (one close
    frame of 300 is still drawn), and the paths keep the frames where a robot is missing (the line breaks)."""
    from robotarium_exp.analysis import plots

    monkeypatch.setattr(plots, 'DRAWN_FRAMES', 40)
    t = np.arange(300) * 0.1
    stamps = np.arange(300, dtype=np.int64) * 100_000_000
    near = np.where(np.arange(300) == 151, 0.05, 1.0)  # one frame, not on the stride, where the two come close
    kept = (np.arange(300) < 77) | (np.arange(300) > 78)  # robot b misses two frames, a gap at 0.15 s
    samples = {
        'a': RobotSamples(stamps, np.stack([t, 0 * t], axis=1)),
        'b': RobotSamples(stamps[kept], np.stack([t, near], axis=1)[kept]),
    }
    result = analyse(assemble(samples, source={'path': 's'}, max_gap=MaxGap.parse('0.15s')), None)
    figures = analysis_figures({'run': result}, None, None)
    (line, *_) = figures['distance'].axes[0].lines
    assert len(line.get_ydata()) <= 40 and np.nanmin(line.get_ydata()) == 0.05
    path_b = figures['paths'].axes[0].lines[1].get_ydata()
    assert len(path_b) < 60 and np.isnan(path_b).sum() == 2  # thinned, and broken where b is missing


def test_every_robot_is_in_every_snapshot_when_stamped_a_few_ms_apart() -> None:
    """Motion capture stamps each body a few milliseconds after the last: frames then hold only some robots, and
    the snapshots still show all four, at their positions interpolated to each snapshot's instant."""
    period, n = 10_000_000, 4
    samples = {}
    for k in range(n):
        stamps = np.arange(200, dtype=np.int64) * period + k * 3_000_000
        t = stamps * 1e-9
        samples[f'r{k}'] = RobotSamples(stamps, np.stack([0.5 * t, 0.3 * k + 0 * t], axis=1))
    trajectory = assemble(samples, source={'path': 'mocap'})
    assert not trajectory.complete_frames()[[0, -1]].any()  # the first and last frames miss robots
    ax = analysis_figures({'run': analyse(trajectory, None)}, None, None)['paths'].axes[0]
    snapshots = [np.ma.filled(c.get_offsets(), np.nan) for c in ax.collections]
    assert len(snapshots) == 7 and all(np.isfinite(s).all() and len(s) == n for s in snapshots)
    for offsets in snapshots:  # all four at one instant (to within the frame window, 5 ms), in their own rows
        np.testing.assert_allclose(offsets[:, 0], offsets[0, 0], atol=0.5 * 0.005 + 1e-12)
        np.testing.assert_allclose(offsets[:, 1], 0.3 * np.arange(n))
    assert '\n' not in ax.get_title()


def test_a_robot_missing_at_a_snapshot_is_named() -> None:
    stamps = np.arange(300, dtype=np.int64) * 100_000_000
    t = stamps * 1e-9
    kept = (t < 14.0) | (t > 16.5)  # b is not seen around the middle snapshot (15 s)
    samples = {
        'a': RobotSamples(stamps, np.stack([t, 0 * t], axis=1)),
        'b': RobotSamples(stamps[kept], np.stack([t, 1 + 0 * t], axis=1)[kept]),
    }
    ax = analysis_figures({'run': analyse(assemble(samples, source={'path': 's'}), None)}, None, None)['paths'].axes[0]
    counts = [int(np.isfinite(np.ma.filled(c.get_offsets(), np.nan)).all(axis=1).sum()) for c in ax.collections]
    assert counts == [2, 2, 2, 1, 2, 2, 2]
    assert ax.get_title().endswith('no position (gap or outside its recording) at 14.9 s: b')
