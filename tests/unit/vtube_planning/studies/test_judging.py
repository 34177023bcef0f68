"""Families of claims and held-out confirmation (`vtube_planning.studies.judging`) on tests whose answer is known."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.studies.judging import (
    Family,
    FamilyError,
    confirmed,
    default_family,
    families_from_toml,
    families_text,
    family_of,
    judge,
)
from vtube_planning.studies.stats import detectable_shift, holm, nonzero_count, paired_difference, signed_rank_p


def paired(cell: int, metric: str, differences: np.ndarray, a: str = 'planning') -> dict:
    """A paired test of a - b in cell ``cell`` (its N) as the reports build it."""
    estimate = paired_difference(differences, np.zeros(differences.size))
    fields = {'a': a, 'b': 'no planning', 'metric': metric, 'better': 'higher', 'n_robots': cell, 'model': 'paper'}
    return fields | {
        'estimate': estimate,
        'p': signed_rank_p(differences),
        'nonzero': nonzero_count(differences),
        'sd': float(np.std(differences, ddof=1)),
    }


def test_a_family_takes_the_tests_it_names_and_the_first_one_wins() -> None:
    d = np.linspace(0.1, 1.0, 10)
    time_20, distance_20, time_40 = paired(20, 'passing_time_s', d), paired(20, 'min_distance_m', d), paired(40, 'x', d)
    faster = Family('faster', ('planning - no planning',), ('passing_time_s',))
    in_20 = Family('N = 20', cells=(('n_robots', (20,)),))
    assert [family_of(t, (faster, in_20)) for t in (time_20, distance_20, time_40)] == [
        'faster',
        'N = 20',
        default_family(time_40),
    ]
    assert family_of(time_20, (in_20, faster)) == 'N = 20'  # in the order declared
    assert default_family(time_40) == 'planning - no planning, x'
    other = paired(20, 'passing_time_s', d, a='planning without (p7)')
    assert not faster.takes(other) and in_20.takes(other)


def test_judging_adjusts_within_each_family_by_holm() -> None:
    """Three cells in one family and one alone: each family's adjusted p-values are Holm's over its own members,
    recomputed here; the shift found at 80 % power is that of the family's size."""
    rng = np.random.default_rng(1)
    tests = [paired(n, 'passing_time_s', rng.normal(shift, 1.0, 12)) for n, shift in ((1, 1.5), (2, 0.3), (3, 1.0))]
    tests.append(paired(9, 'passing_time_s', rng.normal(0.8, 1.0, 12)))
    alone = Family('cell 9', cells=(('n_robots', (9,)),))
    judge(tests, (alone,))
    np.testing.assert_allclose([t['p_holm'] for t in tests[:3]], holm([t['p'] for t in tests[:3]]))
    assert tests[3]['p_holm'] == tests[3]['p'] and tests[3]['family'] == 'cell 9' and tests[3]['size'] == 1
    assert (
        tests[0]['detectable'] == detectable_shift(12, 0.05 / 3) > tests[3]['detectable'] == detectable_shift(12, 0.05)
    )
    text = families_text(tests)
    assert (
        f'- planning - no planning, passing_time_s: 3 claims, 12 pairs each, 80 % power at {detectable_shift(12, 0.05 / 3):.2f} SD'
        in text
    )
    assert '- cell 9: 1 claim, 12 pairs each' in text


def test_held_out_seeds_test_only_the_claims_found_in_a_smaller_family() -> None:
    """Of four cells, two are found on the first seeds; the held-out seeds test those two only (a family of two,
    not four), confirm one and not the other; the two not found are not tested again and keep their verdict."""
    up, flat = np.linspace(0.5, 1.4, 10), np.sin(np.arange(10.0))
    found = judge([paired(1, 't', up), paired(2, 't', up), paired(3, 't', flat), paired(4, 't', flat)], ())
    assert [t['verdict'] for t in found] == ['holds', 'holds', 'not shown', 'not shown']
    again = [paired(1, 't', up), paired(2, 't', flat), paired(3, 't', up), paired(4, 't', up)]
    out = confirmed(found, again, (), lambda t: t['n_robots'])
    assert [t['verdict'] for t in out] == ['holds', 'not replicated', 'not shown', 'not shown']
    assert out[0]['confirmation']['size'] == 2 and out[0]['confirmation']['p_holm'] == pytest.approx(2 * 2 / 1024)
    assert out[2]['confirmation'] is None and out[3]['discovery_verdict'] == 'not shown'


def test_a_families_table_is_read_and_written_back() -> None:
    table = {'faster': {'comparisons': ['planning - no planning'], 'metrics': ['passing_time_s'], 'model': ['paper']}}
    (family,) = families_from_toml(table)
    assert family == Family('faster', ('planning - no planning',), ('passing_time_s',), (('model', ('paper',)),))
    assert family.to_json() == table['faster'] and families_from_toml({}) == ()
    for bad, phrase in (
        ([1], 'must be a table of tables'),
        ({'f': 3}, 'families.f must be a table'),
        ({'f': {}}, 'families.f must be a table'),
        ({'f': {'metrics': 'passing_time_s'}}, 'families.f.metrics must be a list'),
        ({'f': {'model': []}}, 'families.f.model must be a list'),
    ):
        with pytest.raises(FamilyError, match=phrase):
            families_from_toml(bad)
