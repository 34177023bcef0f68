"""The study report: the paired verdicts and the verdict summary on synthetic rows whose answer is known."""

from __future__ import annotations

import numpy as np


def test_the_verdict_summary_counts_cells_on_synthetic_rows() -> None:
    """Two cells: in N = 20 planning is 0.1 m safer and 1 s faster on every seed; in N = 40 nothing differs."""
    from vtube_planning.studies.stats import detectable_shift
    from vtube_planning.studies.study_report import paired_table, verdict_summary

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
        (40, 'passing_time_s'): 'not shown',  # every difference zero (N = 20 lets the family be judged)
        (40, 'min_distance_m'): 'not shown',
    }
    text = verdict_summary(paired_table(rows))
    assert "| setting | planning - no planning (the paper's comparison) |" in text  # the only comparison flown
    assert '| paper model, radial sat | T +1 =1 -0, D +1 =1 -0 |' in text
    shift = detectable_shift(10, 0.05 / 2)  # ten pairs, Holm's first step over the family's two cells
    assert f'- planning - no planning, min_distance_m: 2 claims, 10 pairs each, 80 % power at {shift:.2f} SD' in text


def test_over_random_maps_the_maps_are_the_sample() -> None:
    """Ten maps, three seeds each: planning is faster by a map's own amount d_m (mean 1 s over maps, seeds alike)
    and as safe as without; the estimate is the mean of the d_m, recomputed here, and only time's claim holds."""
    from vtube_planning.studies.study_report import grid_markdown, map_differences, map_summary

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
    assert distance['verdict'] == 'no verdict' and distance['estimate'].value == 0.0  # no non-zero difference
    text = map_summary(rows)
    assert '| 10 bottleneck (clutter 30, opening 4 m) maps, scene C, N = 20 | paper model, radial sat |' in text
    assert '### Scene C on bottleneck (clutter 30, opening 4 m) map 9, N = 20' in grid_markdown(rows)
    assert map_summary([r | {'map': 'none'} for r in rows]) == ''  # no maps: no such table


def cells(gains: list[float], seeds: range, rng: np.random.Generator) -> list[dict]:
    """One cell per gain (N = 1, 2, ...): planning faster by the gain on each seed, give or take 10 %."""
    rows = []
    for n, gain in enumerate(gains, start=1):
        for seed in seeds:
            base = {'scene': 'C', 'n_robots': n, 'seed': seed, 'model': 'paper', 'saturation': 'radial'}
            rows.append(base | {'mode': 'no planning', 'passing_time_s': 20.0, 'min_distance_m': 0.8})
            noisy = 20.0 - gain * (1.0 + rng.normal(0.0, 0.1))
            rows.append(base | {'mode': 'planning', 'passing_time_s': noisy, 'min_distance_m': 0.8})
    return rows


def test_a_verdict_is_adjusted_for_the_cells_compared() -> None:
    """Seven seeds that all agree give p = 2/128 = 0.016: a claim alone, but among twenty cells no claim could be
    significant (Holm: 20 x 0.016 > 0.05), so none gets a verdict; ten such seeds (p = 0.002) hold among twenty."""
    from vtube_planning.studies.study_report import paired_table

    rng = np.random.default_rng(2)
    alone = paired_table(cells([1.0], range(7), rng))
    timed = [p for p in alone if p['metric'] == 'passing_time_s']
    assert [p['verdict'] for p in timed] == ['holds'] and timed[0]['p_holm'] == timed[0]['p'] == 2 / 128
    among = [p for p in paired_table(cells([1.0] * 20, range(7), rng)) if p['metric'] == 'passing_time_s']
    assert {p['verdict'] for p in among} == {'no verdict'} and all(np.isnan(p['p_holm']) for p in among)
    ten = [p for p in paired_table(cells([1.0] * 20, range(10), rng)) if p['metric'] == 'passing_time_s']
    assert {p['verdict'] for p in ten} == {'holds'}
    assert ten[0]['relative'] == ten[0]['estimate'].value / 20.0  # the effect as a share of b's mean


def test_held_out_seeds_confirm_or_not_and_too_few_seeds_get_no_verdict() -> None:
    """Cell 1 is faster on seeds 0-9 and on the held-out seeds 100-109; cell 2 only on 0-9 (the held-out seeds show
    nothing): it is reported as not replicated, both sets side by side; cell 3, faster on neither, is not tested
    again. Pooled instead, cells 1 and 2 hold over the 20 seeds. Four seeds: no verdict."""
    from vtube_planning.studies.judging import Judging
    from vtube_planning.studies.study_report import grid_markdown, paired_table, verdict_summary

    rng = np.random.default_rng(3)
    rows = cells([1.0, 1.0, 0.0], range(10), rng) + cells([1.0, 0.0, 0.0], range(100, 110), rng)
    held = Judging(held_out=tuple(range(100, 110)))
    table = [p for p in paired_table(rows, held) if p['metric'] == 'passing_time_s']
    assert [(p['n_robots'], p['discovery_verdict'], p['verdict']) for p in table] == [
        (1, 'holds', 'holds'),
        (2, 'holds', 'not replicated'),
        (3, 'not shown', 'not shown'),
    ]
    assert table[1]['confirmation']['verdict'] == 'not shown' and table[1]['confirmation']['estimate'].n == 10
    assert table[0]['confirmation']['size'] == 2 and table[2]['confirmation'] is None  # only the claims found
    assert table[0]['size'] == 3
    text = grid_markdown(rows, held)
    assert '=> **not replicated**' in text and '(seeds found on; held-out seeds)' in text
    assert 'not tested again (no claim found)' in text
    assert 'T +1 =1 -0 ~1' in verdict_summary(paired_table(rows, held))
    pooled = [p for p in paired_table(rows) if p['metric'] == 'passing_time_s']
    assert [p['verdict'] for p in pooled] == ['holds', 'holds', 'not shown'] and pooled[0]['estimate'].n == 20
    few = [p for p in paired_table(cells([5.0], range(4), rng)) if p['metric'] == 'passing_time_s']
    assert few[0]['verdict'] == 'no verdict' and np.isnan(few[0]['p_holm'])
    assert 'T +0 =0 -0 ?1' in verdict_summary(paired_table(cells([5.0], range(4), rng)))


def test_declared_families_are_adjusted_apart_and_stated() -> None:
    """Twenty cells of seven unanimous seeds: as one family (the default, per comparison and metric) no claim could
    reach 5 % (20 x 2/128); a declared family of the first cell alone holds it, the other nineteen stay no verdict,
    and the report names both families."""
    from vtube_planning.studies.judging import Family, Judging
    from vtube_planning.studies.study_report import grid_markdown, paired_table

    rng = np.random.default_rng(5)
    rows = cells([1.0] * 20, range(7), rng)
    alone = Family('the first cell', metrics=('passing_time_s',), cells=(('n_robots', (1,)),))
    timed = [p for p in paired_table(rows, Judging((alone,))) if p['metric'] == 'passing_time_s']
    assert [p['verdict'] for p in timed] == ['holds'] + ['no verdict'] * 19
    assert timed[0]['family'] == 'the first cell' and timed[0]['size'] == 1 and timed[0]['p_holm'] == 2 / 128
    assert timed[1]['family'] == 'planning - no planning, passing_time_s' and timed[1]['size'] == 19
    text = grid_markdown(rows, Judging((alone,)))
    assert '- the first cell: 1 claim, 7 pairs each, 80 % power at' in text
    assert '- planning - no planning, passing_time_s: 19 claims, 7 pairs each, 80 % power at no shift' in text


def test_a_claim_not_shown_prints_the_shift_its_seeds_would_find() -> None:
    """Ten seeds, one cell, no effect: 'not shown', with the shift found at 80 % power at 0.05 (in SDs of the
    differences, and in seconds: times their SD)."""
    from vtube_planning.studies.stats import detectable_shift
    from vtube_planning.studies.study_report import grid_markdown, paired_table

    rows = cells([0.0], range(10), np.random.default_rng(6))
    for r in rows:
        r['passing_time_s'] += 0.1 * np.sin(r['seed'] + (r['mode'] == 'planning'))
    (timed,) = [p for p in paired_table(rows) if p['metric'] == 'passing_time_s']
    shift = detectable_shift(10, 0.05)
    x = np.array([r['passing_time_s'] for r in rows if r['mode'] == 'planning'])
    y = np.array([r['passing_time_s'] for r in rows if r['mode'] == 'no planning'])
    assert timed['verdict'] == 'not shown' and timed['detectable'] == shift
    assert f'not shown (80 % power at {shift:.2f} SD = {shift * np.std(x - y, ddof=1):.3g})' in grid_markdown(rows)


def test_every_table_names_its_physics() -> None:
    """The setting names the robot model and, unless the law, the controller; the mode summary says what each mode's
    plan is held to."""
    from vtube_planning.studies.study_report import mode_summary, setting_text

    row = {'scene': 'C', 'n_robots': 20, 'model': 'acceleration limits', 'saturation': 'radial', 'seed': 0}
    assert (
        setting_text(row | {'controller': 'foresight'}) == 'acceleration limits model, radial sat, foresight controller'
    )
    assert setting_text(row | {'controller': 'law'}) == 'acceleration limits model, radial sat'
    rows = [row | {'mode': m, 'collision_pairs': 0, 'completed': True} for m in ('planning (relaxed)', 'no planning')]
    text = mode_summary(rows)
    assert text.startswith('Physics: every mode flies the robot model of its setting')
    assert 'planning (relaxed): a plan from v_max, (p3) and (p4) left out' in text
