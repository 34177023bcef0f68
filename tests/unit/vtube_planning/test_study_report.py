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
