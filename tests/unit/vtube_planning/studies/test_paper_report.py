"""The paper's comparison report: its claim checked on the means and per seed, on rows whose answer is known."""

from __future__ import annotations

from vtube_planning.studies.paper_report import study_markdown, summarise


def _row(mode: str, seed: int, time_s: float, distance_m: float, pairs: int = 0) -> dict[str, object]:
    return {
        'scene': 'C',
        'mode': mode,
        'seed': seed,
        'passing_time_s': time_s,
        'min_distance_m': distance_m,
        'collision_pairs': pairs,
        'incursion_depth_m': 0.0,
        'nmpc_converged_share': float('nan'),
        'tube_violation_steps': 0,
        'completed': True,
    }


def test_the_claim_holds_on_the_means_and_fails_on_the_seed_where_it_fails() -> None:
    rows = [
        _row('planning', 0, 18.0, 0.95),
        _row('planning', 1, 18.0, 0.80),  # seed 1: planning passes closer than without
        _row('no planning', 0, 22.0, 0.85),
        _row('no planning', 1, 22.0, 0.85),
        _row('flocking', 0, 30.0, 0.50, pairs=3),
        _row('flocking', 1, 30.0, 0.60, pairs=1),
    ]
    (entry,) = summarise(rows)
    assert entry['modes'] == ['planning', 'no planning', 'flocking']
    assert entry['planning']['min_distance_m'] == 0.875 and entry['planning']['min_distance_range_m'] == [0.8, 0.95]
    assert entry['claim_on_means']  # 18 < 22 s, 0.875 > 0.85 m, no collision
    assert entry['claim_per_seed'] == [{'seed': 0, 'holds': True}, {'seed': 1, 'holds': False}]
    assert entry['safer_than'] == {'flocking': True} and entry['flocking']['collision_pairs'] == 4
    text = study_markdown([entry], [0, 1], acceleration_limits=False)
    assert 'seeds 0-1 (initial jitter' in text and 'seeds 10-12,20' in study_markdown([entry], [10, 11, 12, 20], False)
    assert '- scene C: holds on the means; per seed it holds for 1 of 2 (not for seed 1).' in text


def test_a_collision_with_planning_breaks_the_claim() -> None:
    rows = [_row('planning', s, 18.0, 0.9, pairs=1) for s in (0, 1)] + [
        _row('no planning', s, 22.0, 0.8) for s in (0, 1)
    ]
    (entry,) = summarise(rows)
    assert not entry['claim_on_means'] and not any(s['holds'] for s in entry['claim_per_seed'])
