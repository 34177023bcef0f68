"""The crossover: per cell the best unplanned mode, the paired verdicts against it, the collisions, the win; its
table in the report and its figure draw those numbers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from matplotlib.patches import Rectangle

from vtube_planning.studies.campaign import Campaign
from vtube_planning.studies.crossover import (
    campaign_report_text,
    crossover_cells,
    crossover_markdown,
    is_crossover,
)
from vtube_planning.studies.judging import POOLED
from vtube_planning.studies.study_plots import crossover_figure
from vtube_planning.studies.study_report import report_text

SEEDS = range(8)
TIMES = {  # (narrowest_m, N): mean passing time per mode (s); NaN at seed 0: that run did not complete
    (0.9, 20): {'planning': 20.0, 'no planning': 23.0, 'no planning at v_max': 21.0},
    (1.5, 20): {'planning': 22.0, 'no planning': 23.0, 'no planning at v_max': 19.0},
    (0.9, 40): {'planning': 20.0, 'no planning': 23.0, 'no planning at v_max': math.nan},
}
DISTANCES = {'planning': 0.8, 'no planning': 0.6, 'no planning at v_max': 0.5}


def rows_of() -> list[dict]:
    """Scene C in the paper's model: the cells of TIMES, seeds 0-7 (noisy); the plan collides once at 1.5 m."""
    rng = np.random.default_rng(5)
    rows = []
    for (width, n), times in TIMES.items():
        for seed in SEEDS:
            for mode, time in times.items():
                late = math.isnan(time) and seed == 0
                collides = (mode == 'planning' and width == 1.5 and seed == 3) or mode == 'no planning at v_max'
                rows.append(
                    {
                        'scene': 'C',
                        'narrowest_m': width,
                        'n_robots': n,
                        'model': 'paper',
                        'saturation': 'radial',
                        'controller': 'law',
                        'mode': mode,
                        'seed': seed,
                        'passing_time_s': math.nan
                        if late
                        else (23.5 if math.isnan(time) else time) + rng.normal(0, 0.1),
                        'min_distance_m': DISTANCES[mode] + rng.normal(0, 0.02),
                        'collision_pairs': int(collides),
                    }
                )
    return rows


def test_each_cell_is_judged_against_its_best_unplanned_mode() -> None:
    rows = rows_of()
    cells = {(c['narrowest_m'], c['n_robots']): c for c in crossover_cells(rows, POOLED)}
    assert set(cells) == set(TIMES)
    assert [cells[k]['best'] for k in TIMES] == ['no planning at v_max', 'no planning at v_max', 'no planning']
    for (width, n), cell in cells.items():
        mine = [r for r in rows if (r['narrowest_m'], r['n_robots']) == (width, n)]
        a, b = (np.array([r['passing_time_s'] for r in mine if r['mode'] == m]) for m in ('planning', cell['best']))
        assert cell['difference_s'] == pytest.approx(float(np.mean(a - b)))  # the paired mean over the seeds
        assert cell['seeds'] == len(SEEDS) and cell['setting'] == 'paper model, radial sat'
        best = sum(r['collision_pairs'] for r in mine if r['mode'] == cell['best'])
        assert (cell['planned_collisions'], cell['best_collisions']) == (int(width == 1.5), best)
    assert (cells[0.9, 20]['time'], cells[0.9, 20]['distance']) == ('holds', 'holds')
    assert cells[0.9, 20]['wins'] and cells[0.9, 20]['safer']
    assert cells[1.5, 20]['time'] == 'reversed' and not cells[1.5, 20]['wins']  # slower than v_max, and collided
    assert cells[1.5, 20]['safer']  # one collision pair against eight
    assert cells[0.9, 40]['wins']  # v_max did not complete once: 3.5 m/s is the best there


def test_a_cell_without_a_test_is_no_win_and_says_so() -> None:
    rows = [r for r in rows_of() if not (r['mode'] == 'planning' and r['seed'] == 0 and r['narrowest_m'] == 1.5)]
    first = next(r for r in rows_of() if (r['mode'], r['seed'], r['narrowest_m']) == ('planning', 0, 1.5))
    rows.append(first | {'passing_time_s': math.nan})  # the plan's run of seed 0 did not complete
    cell = next(c for c in crossover_cells(rows, POOLED) if c['narrowest_m'] == 1.5)
    assert cell['time'] is None and math.isnan(cell['difference_s']) and not cell['wins']
    assert '| paper model, radial sat | C | 1.5 | 20 | no planning at v_max | n/a | n/a |' in crossover_markdown([cell])


def test_the_report_adds_the_crossover_table_only_to_a_crossover_campaign() -> None:
    rows = rows_of()
    modes = ['planning', 'no planning', 'no planning at v_max']
    crossover = Campaign.from_dict({'axes': {'scene': ['C'], 'narrowest_m': [0.9, 1.5], 'mode': modes}})
    plain = Campaign.from_dict({'axes': {'scene': ['C'], 'mode': modes}})
    assert is_crossover(crossover) and not is_crossover(plain)
    assert campaign_report_text(plain, rows, 0, []) == report_text('campaign', rows, 0, POOLED, [])
    text = campaign_report_text(crossover, rows, 0, [])
    assert text.startswith(report_text('campaign', rows, 0, POOLED, []))
    assert '| paper model, radial sat | C | 0.9 | 20 | no planning at v_max | -1.' in text
    assert text.count('| paper model, radial sat | C |') == len(TIMES)
    assert 'Cells (scene, narrowest half-width, N) where a beats b' in text  # the verdict rows count them


def test_the_figure_colours_each_cell_by_its_difference_and_frames_the_wins() -> None:
    rows = rows_of()
    cells = crossover_cells(rows, POOLED)
    fig = crossover_figure(rows)
    panels = [ax for ax in fig.axes if ax.images]
    assert len(panels) == 1  # one scene, one setting
    shown = np.asarray(panels[0].images[0].get_array())
    widths, sizes = [0.9, 1.5], [20, 40]
    for c in cells:
        assert shown[widths.index(c['narrowest_m']), sizes.index(c['n_robots'])] == pytest.approx(c['difference_s'])
    assert np.ma.is_masked(shown[1, 1]) or np.isnan(shown[1, 1])  # no cell at 1.5 m, N = 40
    frames = [p for p in panels[0].patches if isinstance(p, Rectangle)]
    assert len(frames) == sum(c['wins'] for c in cells) == 2
