"""The planned-against-unplanned comparison: its runs (seeds, modes, progress), its rows and its table."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import robotarium_exp.compare as compare_module
from robotarium_exp.compare import COLUMNS, ComparisonRow, comparison_table, failed_runs
from robotarium_exp.verifier import VerifierCounts
from tests.support.passage import metrics


def row(seed: int, planned: bool, **change) -> ComparisonRow:
    values = {
        'passing_time_s': 30.0 + seed,
        'min_distance_m': 0.2 + 0.01 * seed,
        'tube_violation_steps': seed,
        'intervention_m': 1.0,
        'band_percent': 99.0,
        'approach_percent': 10.0,
        'dip_percent': 20.0,
        'expansion_start_s': 3.0 if planned else None,
        'front_at_narrowing_s': 12.0,
        'testbed_errors': 0,
    }
    return ComparisonRow(seed=seed, planned=planned, **(values | change))


def test_the_table_gives_mean_and_range_per_mode() -> None:
    rows = [row(0, True), row(0, False), row(2, True), row(2, False, dip_percent=None)]
    lines = comparison_table(rows).splitlines()
    assert lines[:2] == ['| measure | planned | unplanned |', '|---|---|---|'] and len(lines) == 2 + len(COLUMNS)
    assert lines[2] == '| passing time [s] | 31.0 [30.0, 32.0] | 31.0 [30.0, 32.0] |'
    assert lines[3] == '| min distance [m] | 0.210 [0.200, 0.220] | 0.210 [0.200, 0.220] |'
    assert '| density error, dip [%] | 20 [20, 20] | 20 [20, 20] |' in lines  # the None is left out
    assert '| expansion starts [s] | 3.0 [3.0, 3.0] | never |' in lines
    no_dip = comparison_table([row(0, True, dip_percent=None)])
    assert '| density error, dip [%] | – | – |' in no_dip.splitlines()


def test_a_row_is_strict_json() -> None:
    data = row(1, True, min_distance_m=math.inf, passing_time_s=math.nan).to_json()
    assert data['min_distance_m'] is None and data['passing_time_s'] is None and data['seed'] == 1
    assert set(data) == {'seed', 'planned', 'failures'} | {key for _, key, _ in COLUMNS} and data['failures'] == []


def test_compare_runs_both_modes_per_seed_on_the_same_draws(monkeypatch) -> None:
    """run_experiment and plan_tracking stubbed: the loop's order, the seeding, the rows' fields, progress."""
    runs: list[tuple[int, bool]] = []
    seeded: list[int] = []
    monkeypatch.setattr(compare_module, 'seed_rps', seeded.append)

    def run(cls, scene, plan, config, robotarium_kwargs):
        assert robotarium_kwargs == {'testbed_model': 'fitted:2'}  # the model reaches every run's simulator
        runs.append((seeded[-1], config.planning))
        assert (plan is not None) == config.planning
        return SimpleNamespace(
            arrays={},
            metrics=metrics(passing_time_s=20.0, min_distance_m=0.25, tube_violation_steps=int(config.planning)),
            barrier=SimpleNamespace(intervention_m=0.5, band_share=0.97),
            errors=VerifierCounts(1, 2, 3) if config.planning else VerifierCounts(),
            duration_s=60.0,
            completed=True,
        )

    phase = SimpleNamespace(density_error_mean=0.125)
    tracked = SimpleNamespace(approach=phase, dip=SimpleNamespace(density_error_mean=None), expansion_start_s=4.0,
                              front_at_narrowing_s=9.0)  # fmt: skip
    monkeypatch.setattr(compare_module, 'run_experiment', run)
    monkeypatch.setattr(compare_module, 'plan_tracking', lambda arrays, plan, scene: tracked)
    done: list[int] = []
    rows = compare_module.compare(
        SimpleNamespace(), SimpleNamespace(), [5, 7], run_done=lambda: done.append(1), testbed_model='fitted:2'
    )  # type: ignore[arg-type]
    assert runs == [(5, True), (5, False), (7, True), (7, False)] and seeded == [5, 5, 7, 7] and len(done) == 4
    assert [(r.seed, r.planned) for r in rows] == runs
    r = rows[0]
    assert (r.band_percent, r.approach_percent, r.dip_percent, r.testbed_errors) == (
        pytest.approx(97.0),
        12.5,
        None,
        6,
    )
    assert np.isclose(r.intervention_m, 0.5) and r.expansion_start_s == 4.0
    assert rows[1].failures == () and failed_runs(rows) == (
        'seed 5, planned: ' + '; '.join(rows[0].failures),
        'seed 7, planned: ' + '; '.join(rows[2].failures),
    )
    assert rows[0].failures[0].startswith('the testbed would not run it (1 pair-steps of robots too close, 2 ')
    # one verdict, as the check's: actuator-limit steps fail
    assert rows[0].failures[1] == 'the simulator counted 3 steps over the wheel-speed limit'
    assert rows[0].failures[2].startswith('robot bodies were on the tube walls in 1 robot-steps')


def test_paired_claims_are_tested_in_their_own_families_and_confirmed_on_held_out_seeds() -> None:
    """Planned passes sooner on seeds 0-9 and on the held-out seeds 20-29; its filter intervenes less only on
    0-9 (on 20-29 by as much): passing time holds, the intervention is not replicated; the minimum distance, equal
    in both modes, gives no verdict (no non-zero difference) and the band, found on neither, is not tested again;
    with four seeds, no verdict. Each measure is its own family: ten seeds that all agree give p = 2/1024, not
    multiplied by the eight measures; pooled, the twenty seeds give 2/2**20."""
    from robotarium_exp.compare import paired_table

    rows = []
    for seed in [*range(10), *range(20, 30)]:
        jitter = 0.1 * np.sin(seed)
        less = 0.5 if seed < 20 else 0.0
        band = 99.0 + 0.1 * np.cos(seed)
        rows += [row(seed, True, passing_time_s=28.0 + seed + jitter, intervention_m=1.0 - less + jitter)]
        rows += [row(seed, False, band_percent=band)]
    lines = paired_table(rows, confirm_seeds=range(20, 30)).splitlines()
    assert lines[2] == '| planned - unplanned, same seeds | seeds found on | held-out seeds | verdict |'
    by = {line.split(' | ')[0][2:]: line for line in lines[4:]}
    assert by['passing time [s]'].endswith('| **holds** |') and 'p 0.00195, 10 seeds: holds' in by['passing time [s]']
    assert by['filter intervention [m]'].endswith('| **not replicated** |')
    assert by['min distance [m]'].endswith('| **no verdict** |')  # the same in both modes
    assert 'not tested again (no claim found) | **not shown** |' in by['speed band [%]']
    assert 'expansion starts [s]' not in by  # a timing, not a claim
    pooled = {line.split(' | ')[0][2:]: line for line in paired_table(rows).splitlines()[4:]}
    assert 'p 1.91e-06, 20 seeds: **holds**' in pooled['passing time [s]']
    assert '20 seeds: **not shown** (80 % power at' in pooled['speed band [%]']
    few = paired_table([r for r in rows if r.seed < 4])
    assert '4 seeds: **no verdict**' in few and 'p n/a' in few


@pytest.mark.parametrize('scene', ['robotarium_curve', 'robotarium_trapezoid'])
def test_the_committed_comparison_tables_are_what_the_code_gives_from_their_rows(scene: str) -> None:
    """docs/robotarium_compare/: the measures and the paired verdicts, written again from the rows beside them."""
    import json
    from pathlib import Path

    from robotarium_exp.compare import paired_table

    folder = Path(__file__).resolve().parents[3] / 'docs' / 'robotarium_compare'
    recorded = json.loads((folder / f'compare_{scene}.json').read_text(encoding='utf-8'))
    rows = [ComparisonRow(**(r | {'failures': tuple(r['failures'])})) for r in recorded]
    text = (folder / f'compare_{scene}.md').read_text(encoding='utf-8')
    assert f'\n\n{comparison_table(rows)}\n{paired_table(rows)}\n' in text
