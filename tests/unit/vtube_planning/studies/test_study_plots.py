"""Figures of a study: the bars, intervals and shares drawn are the summary's and the rows' own numbers."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.colors import to_rgba

from vtube_planning.studies.stats import mean_interval
from vtube_planning.studies.study_plots import cell_means_figure, paired_differences_figure, study_figure
from vtube_planning.studies.study_report import paired_table


def summary_entry(scene: str, modes: dict[str, tuple[float, float]]) -> dict:
    entry: dict = {'scene': scene, 'modes': list(modes)}
    for mode, (t, d) in modes.items():
        entry[mode] = {
            'passing_time_s': t,
            'passing_time_range_s': [t - 1, t + 1],
            'min_distance_m': d,
            'min_distance_range_m': [d - 0.1, d + 0.1],
        }
    return entry


def rows_of() -> list[dict]:
    """Scene C, N = 20: planning 1 s faster and 0.1 m farther on every seed (noisy); the first no-planning run collides."""
    rng = np.random.default_rng(3)
    rows = []
    for seed in range(6):
        base = {'scene': 'C', 'n_robots': 20, 'seed': seed, 'model': 'paper', 'saturation': 'radial'}
        noise = rng.normal(0.0, 0.05)
        rows.append(base | {'mode': 'no planning', 'passing_time_s': 20.0 + noise, 'min_distance_m': 0.5 + noise,
                            'collision_pairs': int(seed == 0)})  # fmt: skip
        rows.append(base | {'mode': 'planning', 'passing_time_s': 19.0 + noise + rng.normal(0, 0.01),
                            'min_distance_m': 0.6 + noise, 'collision_pairs': 0})  # fmt: skip
    return rows


def test_the_study_figure_has_a_bar_per_scene_and_mode_at_its_mean() -> None:
    summary = [
        summary_entry('A', {'planning': (10.0, 0.7), 'no planning': (12.0, 0.5)}),
        summary_entry('D', {'planning': (11.0, 0.6), 'no planning': (14.0, 0.4), 'flocking': (13.0, 0.2)}),
    ]
    fig = study_figure(summary, collision_distance_m=0.2)
    ax_t, ax_d = fig.axes[:2]
    heights = sorted(round(p.get_height(), 9) for p in ax_t.patches)
    assert heights == [10.0, 11.0, 12.0, 13.0, 14.0]  # flocking only on D
    assert sorted(round(p.get_height(), 9) for p in ax_d.patches) == [0.2, 0.4, 0.5, 0.6, 0.7]
    assert [t.get_text() for t in ax_t.get_xticklabels()] == ['A', 'D']
    collision = next(ln for ln in ax_d.get_lines() if ln.get_label() == '2 r_p (collision)')
    assert collision.get_ydata()[0] == 0.2
    segments = [s for c in ax_t.collections for s in c.get_segments()]
    assert sorted(float(s[0, 1]) for s in segments) == [9.0, 10.0, 11.0, 12.0, 13.0]  # the ranges' lower ends
    assert fig.get_suptitle() == 'bars: mean over the seeds; black lines: from the smallest to the largest value'
    (legend,) = fig.legends
    assert 'min-max over the seeds' in [text.get_text() for text in legend.get_texts()]
    named = study_figure(summary, collision_distance_m=0.2, seeds=(0, 1, 2, 3, 4))
    assert named.get_suptitle().startswith('bars: mean over seeds 0-4;')


def test_the_paired_figure_draws_each_difference_with_its_interval() -> None:
    rows = rows_of()
    fig = paired_differences_figure(rows)
    table = {p['metric']: p for p in paired_table(rows)}
    for ax, metric in zip(fig.axes, ('passing_time_s', 'min_distance_m'), strict=True):
        estimate = table[metric]['estimate']
        point = ax.get_lines()[0]
        assert point.get_xdata()[0] == pytest.approx(estimate.value)
        (segment,) = ax.collections[0].get_segments()
        np.testing.assert_allclose(segment[:, 0], [estimate.low, estimate.high])
    assert table['passing_time_s']['verdict'] == table['min_distance_m']['verdict'] == 'holds'


def test_the_cell_means_figure_draws_means_intervals_and_collision_shares() -> None:
    rows = rows_of()
    fig = cell_means_figure(rows)
    time_ax, distance_ax, share_ax = fig.axes[:3]
    assert len(fig.axes) == 3  # one scene: one row of three panels
    for mode_k, mode in enumerate(('no planning', 'planning')):
        values = np.array([r['passing_time_s'] for r in rows if r['mode'] == mode])
        point = time_ax.get_lines()[mode_k]
        assert point.get_xdata()[0] == pytest.approx(values.mean())
        segment = time_ax.collections[mode_k].get_segments()[0]
        e = mean_interval(values)
        np.testing.assert_allclose(segment[:, 0], [e.low, e.high])
    shares = sorted(round(p.get_width(), 9) for p in share_ax.patches)
    assert shares == [0.0, round(1 / 6, 9)]
    assert distance_ax.get_title() == 'scene C: min distance [m]'


def test_the_map_figure_draws_a_dot_per_map_and_the_interval_over_maps() -> None:
    from vtube_planning.studies.study_plots import map_differences_figure
    from vtube_planning.studies.study_report import map_differences

    rows = []
    for map_seed in range(4):  # on map k, planning is k + 1 s faster (rows_of's 1 s and k more)
        for r in rows_of():
            gain = float(map_seed) if r['mode'] == 'planning' else 0.0
            rows.append(r | {'map': 'forest', 'map_seed': map_seed, 'map_clutter': 30, 'map_width_m': 4.0}
                        | {'passing_time_s': r['passing_time_s'] - gain})  # fmt: skip
    found = {f['metric']: f for f in map_differences(rows)}
    time = found['passing_time_s']
    assert np.allclose(time['per_map'], [-1.0, -2.0, -3.0, -4.0], atol=0.01)
    fig = map_differences_figure(rows)
    ax = fig.axes[0]
    dots = [line for line in ax.lines if line.get_marker() == '.']
    assert len(dots) == 1 and sorted(dots[0].get_xdata()) == sorted(time['per_map'])
    assert [t.get_text() for t in ax.get_yticklabels()] == [
        'planning - no planning  |  4 forest maps, scene C, N=20, paper model, radial sat'
    ]
    (interval,) = ax.collections
    assert np.allclose(interval.get_segments()[0][:, 0], [time['estimate'].low, time['estimate'].high])


def test_the_verdict_matrix_shows_each_comparison_of_each_cell_at_a_glance() -> None:
    """A square per cell and comparison-metric, coloured by its verdict and marked with its effect; a legend of the
    verdicts shown; a second setting is a second row."""
    from vtube_planning.studies.study_plots import VERDICT_COLORS, verdict_matrix_figure

    rows = rows_of() + [r | {'saturation': 'forward', 'collision_pairs': 0} for r in rows_of()]
    table = paired_table(rows)
    fig = verdict_matrix_figure(rows)
    ax = fig.axes[0]
    assert [t.get_text() for t in ax.get_yticklabels()] == [
        'Scene C, N=20, paper model, radial sat',
        'Scene C, N=20, paper model, forward sat',
    ]
    assert [t.get_text() for t in ax.get_xticklabels()] == [
        'planning - no planning: passing time',
        'planning - no planning: min distance',
    ]
    assert len(ax.patches) == len(table) == 4
    colours = sorted(tuple(p.get_facecolor()) for p in ax.patches)
    assert colours == sorted(to_rgba(VERDICT_COLORS[p['verdict']]) for p in table)
    effects = sorted(t.get_text() for t in ax.texts)
    assert effects == sorted(f'{p["relative"]:+.0%}' for p in table)
    assert {p['verdict'] for p in table} == {'no verdict'}  # six seeds in two cells: none could pass Holm (2 x 2/64)
    assert [t.get_text() for t in fig.legends[0].get_texts()] == ['no verdict']


def test_a_scene_without_collisions_says_so_and_the_share_axis_is_named() -> None:
    rows = [r | {'collision_pairs': 0} for r in rows_of()]
    share_ax = cell_means_figure(rows).axes[2]
    assert share_ax.get_xlabel() == 'share of runs with a collision'
    assert [t.get_text() for t in share_ax.texts] == ['no collision\nin any run']


def test_the_verdict_matrix_without_a_comparison_says_so() -> None:
    from vtube_planning.studies.study_plots import verdict_matrix_figure

    one_seed = [r for r in rows_of() if r['seed'] == 0]
    (ax,) = verdict_matrix_figure(one_seed).axes
    assert [t.get_text() for t in ax.texts] == ['no paired comparison: two seeds of both modes are needed']
