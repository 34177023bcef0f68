"""The study report: the paired verdicts and the verdict summary on synthetic rows whose answer is known."""

from __future__ import annotations

import numpy as np


def test_the_verdict_summary_counts_cells_on_synthetic_rows() -> None:
    """Two cells: in N = 20 planning is 0.1 m safer and 1 s faster on every seed; in N = 40 nothing differs."""
    from vtube_planning.study_report import paired_table, verdict_summary

    rng = np.random.default_rng(0)
    rows = []
    for n, gain in ((20, 1.0), (40, 0.0)):
        for seed in range(10):
            base = {'scene': 'C', 'n_robots': n, 'seed': seed, 'model': 'paper', 'saturation': 'radial'}
            spread = rng.normal(0.0, 0.02)
            rows.append(base | {'mode': 'no planning', 'passing_time_s': 20.0, 'min_distance_m': 0.8 + spread})
            rows.append(
                base
                | {
                    'mode': 'planning',
                    'passing_time_s': 20.0 - gain + rng.normal(0.0, 0.01) * gain,
                    'min_distance_m': 0.8 + spread + 0.1 * gain + rng.normal(0.0, 0.005) * gain,
                }
            )
    verdicts = {(p['n_robots'], p['metric']): p['verdict'] for p in paired_table(rows)}
    assert verdicts == {
        (20, 'passing_time_s'): 'holds',
        (20, 'min_distance_m'): 'holds',
        (40, 'passing_time_s'): 'does not hold',
        (40, 'min_distance_m'): 'does not hold',
    }
    text = verdict_summary(rows)
    assert "| setting | planning - no planning (the paper's comparison) |" in text  # the only comparison flown
    assert '| paper model, radial sat | T +1 =1 -0, D +1 =1 -0 |' in text


def test_over_random_maps_the_maps_are_the_sample() -> None:
    """Ten maps, three seeds each: planning is faster by a map's own amount d_m (mean 1 s over maps, seeds alike)
    and as safe as without; the estimate is the mean of the d_m, recomputed here, and only time's claim holds."""
    from vtube_planning.study_report import grid_markdown, map_differences, map_summary

    rng = np.random.default_rng(1)
    gains = rng.uniform(0.5, 1.5, 10)
    gains += 1.0 - gains.mean()
    rows = []
    for map_seed, gain in enumerate(gains):
        for seed in range(3):
            base = {'scene': 'C', 'n_robots': 20, 'seed': seed, 'model': 'paper', 'saturation': 'radial'}
            base |= {'map': 'bottleneck', 'map_seed': map_seed, 'map_clutter': 30, 'map_width_m': 4.0}
            distance = 0.9 + rng.normal(0.0, 0.01)
            rows.append(base | {'mode': 'no planning', 'passing_time_s': 25.0, 'min_distance_m': distance})
            rows.append(base | {'mode': 'planning', 'passing_time_s': 25.0 - gain, 'min_distance_m': distance})
    found = {f['metric']: f for f in map_differences(rows)}
    time, distance = found['passing_time_s'], found['min_distance_m']
    assert np.allclose(time['per_map'], -gains) and abs(time['estimate'].value + 1.0) < 1e-12
    assert time['verdict'] == 'holds' and time['counts'] == '+10 =0 -0'  # each map's seeds alike: a point
    assert distance['verdict'] == 'does not hold' and distance['estimate'].value == 0.0
    text = map_summary(rows)
    assert '| 10 bottleneck (clutter 30, opening 4 m) maps, scene C, N = 20 | paper model, radial sat |' in text
    assert '### Scene C on bottleneck (clutter 30, opening 4 m) map 9, N = 20' in grid_markdown(rows)
    assert map_summary([r | {'map': 'none'} for r in rows]) == ''  # no maps: no such table
