"""The delay margin: the exact failure bound (oracle: scipy.stats' binomial test), the climb on stubs of "clean at
multiple m" (monotone and not), the reuse of runs already flown, the text, the JSON and the header read back."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import pytest
from scipy.stats import binomtest

from robotarium_exp.rps import testbed_model as models
from robotarium_exp.spec import ROBOTARIUM
from submission.delay_margin import (
    LADDER,
    MIN_SEEDS,
    DelayMargin,
    Rung,
    climb,
    failure_bound,
    from_header,
    model_at,
    search,
)
from submission.errors import CheckError


@pytest.mark.parametrize(('failed', 'runs'), [(0, 10), (0, 20), (1, 10), (3, 10), (2, 37), (9, 10), (0, 1)])
def test_the_failure_bound_is_the_exact_one_sided_95_percent_bound(failed: int, runs: int) -> None:
    """One-sided 95 % upper bound = the upper end of the two-sided 90 % Clopper-Pearson interval."""
    oracle = binomtest(failed, runs).proportion_ci(confidence_level=0.90, method='exact').high
    assert failure_bound(failed, runs) == pytest.approx(oracle, rel=1e-9)


def test_the_failure_bound_of_clean_runs_and_of_all_failed() -> None:
    assert failure_bound(0, 10) == pytest.approx(1 - 0.05 ** (1 / 10), rel=1e-12)  # 0.2589: "26 %"
    assert round(100 * failure_bound(0, 10)) == 26
    assert failure_bound(10, 10) == 1.0 and failure_bound(0, 30) < failure_bound(0, 10)
    for failed, runs in [(1, 0), (-1, 5), (6, 5)]:
        with pytest.raises(ValueError, match='0 <= failed <= runs'):
            failure_bound(failed, runs)


def test_the_multiples_are_the_fitted_models_scaled() -> None:
    assert [model_at(m) for m in LADDER[:4]] == ['fitted', 'fitted:1.5', 'fitted:2', 'fitted:2.5']
    fitted = models.testbed_model('fitted')
    scaled = models.testbed_model(model_at(2.5))
    assert scaled.delay_v_steps == pytest.approx(2.5 * fitted.delay_v_steps)
    assert scaled.lag_s == pytest.approx(2.5 * fitted.lag_s)


def stub(clean: set[float], seeds: int = MIN_SEEDS, closest_m: float = 0.2):
    """'Clean at multiple m': every run clean where m is in ``clean``, else the last two runs fail, 0.013 m apart."""
    asked: list[float] = []

    def runs_at(multiple: float) -> list[tuple[bool, float | None]]:
        asked.append(multiple)
        ok = multiple in clean
        return [(ok or k < seeds - 2, closest_m if ok or k < seeds - 2 else 0.013) for k in range(seeds)]

    return runs_at, asked


def test_a_monotone_file_keeps_the_last_clean_multiple_and_the_climb_stops_at_the_first_failure() -> None:
    runs_at, asked = stub({1.0, 1.5, 2.0})
    margin = DelayMargin(climb(runs_at), MIN_SEEDS)
    assert asked == [1.0, 1.5, 2.0, 2.5] and margin.multiple == 2.0 and not margin.top
    assert [(r.multiple, r.runs, r.failed) for r in margin.rungs] == [
        (1, 10, 0),
        (1.5, 10, 0),
        (2, 10, 0),
        (2.5, 10, 2),
    ]
    assert margin.rungs[-1].closest_centres_m == 0.013 and margin.rungs[0].closest_centres_m == 0.2


def test_a_non_monotone_file_keeps_the_multiple_below_its_first_failure() -> None:
    """Clean at 1x and 2x but not at 1.5x: the margin is 1x, and 2x is not tried."""
    runs_at, asked = stub({1.0, 2.0, 3.0})
    margin = DelayMargin(climb(runs_at), MIN_SEEDS)
    assert asked == [1.0, 1.5] and margin.multiple == 1.0
    runs_at, asked = stub({1.5, 2.0})
    none = DelayMargin(climb(runs_at), MIN_SEEDS)
    assert asked == [1.0] and none.multiple is None
    assert none.summary().startswith('Delay margin: none: a run failed at 1x the fitted delay and lag')
    assert from_header(none.summary()) == DelayMargin((), MIN_SEEDS)  # the summary alone: its rungs are not there


def test_a_file_clean_over_the_whole_ladder_keeps_at_least_its_top() -> None:
    runs_at, asked = stub(set(LADDER))
    margin = DelayMargin(climb(runs_at), 12)
    assert asked == list(LADDER) and margin.top and margin.multiple == LADDER[-1]
    assert f'Delay margin: {LADDER[-1]:g}x or more the fitted delay and lag' in margin.summary()


@dataclass(frozen=True)
class Run:
    seed: int | None
    ok: bool
    min_center_distance_m: float | None


def test_the_search_flies_only_what_the_check_has_not_flown() -> None:
    seeds = tuple(range(10))
    flown = {'fitted': [Run(s, True, 0.3) for s in (0, 1, 2)], 'fitted:2': [Run(s, True, 0.25) for s in (0, 1, 2)]}
    batches: list[list[tuple]] = []

    def fly(jobs):
        batches.append(jobs)
        return [Run(seed, model != 'fitted:2.5' or seed != 4, 0.2) for _, seed, model in jobs]

    margin, runs = search(fly, seeds, flown)
    assert [len(b) for b in batches] == [7, 10, 7, 10]  # 1x and 2x: seeds 3-9 only
    assert batches[0] == [('bundled', s, 'fitted') for s in range(3, 10)]
    assert batches[3][0] == ('bundled', 0, 'fitted:2.5')
    assert margin.multiple == 2.0 and margin.seeds == 10 and len(runs) == 40
    assert runs[:3] == flown['fitted'] and margin.rungs[-1].failed == 1
    with pytest.raises(CheckError, match='at least 10 seeds'):
        search(fly, range(9), {})


def test_a_rung_says_its_bound_and_its_distances_as_what_they_are() -> None:
    clean = Rung(2.0, 10, 0, 0.127)
    assert clean.line() == (
        'at 2x: 0 of 10 runs failed: at most 26 % of runs may fail; closest centres 0.127 m, '
        f'a {round(1000 * (0.127 - ROBOTARIUM.robot_diameter_m))} mm gap between bodies.'
    )
    assert ROBOTARIUM.robot_diameter_m == pytest.approx(0.11) and 'a 17 mm gap' in clean.line()
    close = Rung(3.0, 10, 4, 0.013)
    assert 'at 3x: 4 of 10 runs failed: at most 70 % of runs may fail' in close.line()
    assert 'bodies overlapping by 97 mm' in close.line()
    assert Rung(1.0, 10, 10, math.nan).line().endswith('no distance recorded.')


def test_the_margin_in_json_and_read_back_from_its_header_lines() -> None:
    margin = DelayMargin((Rung(1.0, 10, 0, 0.185), Rung(1.5, 10, 0, 0.1504), Rung(2.0, 10, 3, math.nan)), 10)
    data = json.loads(json.dumps(margin.to_json()))
    assert data['multiple'] == 1.5 and data['seeds'] == 10 and data['model_version'] == models.FITTED_VERSION
    assert not data['at_least'] and [r['model'] for r in data['rungs']] == ['fitted', 'fitted:1.5', 'fitted:2']
    assert data['rungs'][0]['failure_rate_upper_95'] == pytest.approx(failure_bound(0, 10))
    assert data['rungs'][0]['gap_between_bodies_m'] == pytest.approx(0.185 - ROBOTARIUM.robot_diameter_m)
    assert data['rungs'][2]['closest_centres_m'] is None and data['rungs'][2]['failed'] == 3
    later = '  at 9x: 0 of 10 runs failed: at most 26 % of runs may fail; no distance recorded.'  # not the margin's
    header = '"""\nSomething before.\n' + '\n'.join(margin.header_lines()) + f'\nPlan: after.\n{later}\n"""\n'
    back = from_header(header)
    assert (
        back is not None and back.multiple == 1.5 and back.seeds == 10 and back.model_version == models.FITTED_VERSION
    )
    assert back.rungs[:1] == margin.rungs[:1] and back.rungs[1].closest_centres_m == 0.150  # as printed
    assert math.isnan(back.rungs[2].closest_centres_m) and back.rungs[2].failed == 3
    assert from_header('no margin here') is None
