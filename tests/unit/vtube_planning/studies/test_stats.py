"""Bootstrap intervals and paired differences on synthetic data whose answer is known."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.errors import ParamsError
from vtube_planning.studies.stats import (
    MIN_SEEDS,
    NO_VERDICT,
    NOT_REPLICATED,
    NOT_SHOWN,
    Estimate,
    cell_values,
    critical_sum,
    detectable_shift,
    family_level,
    holm,
    mean_interval,
    nonzero_count,
    paired_difference,
    quantile_interval,
    relative,
    replicated,
    signed_rank_p,
    verdict,
)


def test_the_mean_interval_covers_the_true_mean_about_95_percent_of_the_time() -> None:
    rng = np.random.default_rng(1)
    covered = sum((e := mean_interval(rng.normal(3.0, 1.0, 20), seed=k)).low <= 3.0 <= e.high for k in range(200))
    assert 176 <= covered <= 198  # 95 % of 200 is 190; BCa with n = 20 runs slightly narrow


def test_the_interval_width_shrinks_like_one_over_root_n() -> None:
    rng = np.random.default_rng(2)
    small, large = mean_interval(rng.normal(0.0, 1.0, 25)), mean_interval(rng.normal(0.0, 1.0, 400))
    ratio = (small.high - small.low) / (large.high - large.low)
    assert 2.8 < ratio < 5.6  # sqrt(400 / 25) = 4
    assert large.high - large.low == pytest.approx(2 * 1.96 / 20, rel=0.2)  # 2 z sigma / sqrt(n)


def test_pairing_removes_what_the_seed_does_to_both_modes() -> None:
    """Seeds shift both modes by up to +/-1; mode a is better by 0.05 on every seed."""
    rng = np.random.default_rng(3)
    seed_effect = rng.uniform(-1.0, 1.0, 10)
    a = seed_effect + 0.05 + rng.normal(0.0, 0.01, 10)
    b = seed_effect
    paired = paired_difference(a, b)
    assert paired.low > 0.0 and paired.low <= 0.05 <= paired.high
    p = signed_rank_p(a - b)
    assert p == pytest.approx(2 / 2**10)  # every seed agrees: the exact test's smallest two-sided p-value
    assert verdict(paired, 'higher', p) == 'holds' and verdict(paired, 'lower', p) == 'reversed'
    assert verdict(paired, 'higher', 0.06) == NOT_SHOWN  # significant only after the adjustment allows
    unpaired_a, unpaired_b = mean_interval(a), mean_interval(b)
    assert unpaired_a.low < unpaired_b.high  # the unpaired intervals overlap: they could not tell


def test_no_difference_is_not_shown() -> None:
    rng = np.random.default_rng(4)
    same = paired_difference(rng.normal(0.0, 1.0, 12), rng.normal(0.0, 1.0, 12))
    assert same.low < 0.0 < same.high and verdict(same, 'higher', 0.001) == NOT_SHOWN  # the interval decides too


def test_quantile_interval_of_a_known_distribution() -> None:
    rng = np.random.default_rng(5)
    x = rng.uniform(0.0, 1.0, 2000)
    q5 = quantile_interval(x, 0.05)
    assert q5.low <= 0.05 <= q5.high and q5.high - q5.low < 0.03
    assert q5.value == pytest.approx(np.quantile(x, 0.05))


def test_degenerate_and_bad_samples() -> None:
    assert mean_interval([2.0, 2.0, 2.0]) == Estimate(2.0, 2.0, 2.0, 3)
    rare = mean_interval([0.0] * 9 + [1.0])  # one collision in ten seeds: a finite interval around 0.1
    assert rare.low == 0.0 and 0.1 < rare.high < 0.6
    with pytest.raises(ParamsError, match='at least two finite values'):
        mean_interval([1.0])
    with pytest.raises(ParamsError, match='one of each per seed; got 3 and 2'):
        paired_difference([1.0, 2.0, 3.0], [1.0, 2.0])
    with pytest.raises(ParamsError, match='strictly between 0 and 1'):
        quantile_interval([1.0, 2.0], 1.0)


def test_cell_values_are_ordered_by_seed_and_filtered() -> None:
    rows = [
        {'mode': 'a', 'seed': 2, 'x': 20.0},
        {'mode': 'b', 'seed': 0, 'x': 1.0},
        {'mode': 'a', 'seed': 0, 'x': 0.0},
        {'mode': 'a', 'seed': 1, 'x': 10.0},
    ]
    np.testing.assert_array_equal(cell_values(rows, 'x', mode='a'), [0.0, 10.0, 20.0])


def test_signed_rank_p_against_the_exact_distribution_enumerated() -> None:
    """Small samples without ties: the two-sided p-value is the share of the 2**n sign assignments whose signed-rank
    sum is at least as far from its centre as the observed one's (counted here by brute force)."""
    import itertools

    rng = np.random.default_rng(6)
    for n in (6, 7, 9):
        d = rng.normal(0.3, 1.0, n)
        ranks = np.argsort(np.argsort(np.abs(d))) + 1
        observed = ranks[d > 0].sum()
        centre = n * (n + 1) / 4
        sums = [ranks[np.array(signs, dtype=bool)].sum() for signs in itertools.product([0, 1], repeat=n)]
        exact = np.mean([abs(t - centre) >= abs(observed - centre) - 1e-9 for t in sums])
        assert signed_rank_p(d) == pytest.approx(exact)
    assert signed_rank_p(np.zeros(8)) == 1.0 and signed_rank_p([0.0, 0.0, 0.5, 0.7, 0.9, 1.1, 1.3, 1.7]) < 0.05


def test_signed_rank_p_with_ties_against_the_enumeration_and_scipy() -> None:
    """Tied magnitudes get mid-ranks and the p-value stays the enumerated share (not a random permutation test);
    without ties it is scipy's exact p-value up to 50 differences, and the normal approximation above."""
    import itertools

    from scipy import stats as scipy_stats

    rng = np.random.default_rng(8)
    for n in (6, 9, 12, 14):
        d = np.round(rng.normal(0.4, 1.0, n), 1)  # rounding makes ties and zeros
        d[:2] = [0.3, -0.3]
        nonzero = d[d != 0.0]
        ranks = scipy_stats.rankdata(np.abs(nonzero))
        observed, centre = ranks[nonzero > 0].sum(), ranks.sum() / 2
        sums = (ranks[np.array(s, dtype=bool)].sum() for s in itertools.product([0, 1], repeat=nonzero.size))
        exact = np.mean([abs(t - centre) >= abs(observed - centre) - 1e-9 for t in sums])
        assert signed_rank_p(d) == pytest.approx(exact, rel=1e-12)
    for n in (20, 50, 51, 80):
        d = rng.normal(0.3, 1.0, n)
        assert signed_rank_p(d) == pytest.approx(scipy_stats.wilcoxon(d).pvalue, rel=1e-9)


def test_holm_against_its_definition_on_random_families() -> None:
    """Adjusted p-values: the running maximum of (m - k + 1) p_(k) in ascending order, capped at 1; rejecting where
    it is below alpha is the step-down rule (reject the smallest while p_(k) < alpha / (m - k + 1))."""
    rng = np.random.default_rng(7)
    for _ in range(200):
        p = rng.uniform(0.0, 0.2, int(rng.integers(1, 30))) ** 2
        adjusted = holm(p)
        order = np.argsort(p)
        m = p.size
        expected = np.minimum(1.0, np.maximum.accumulate([(m - k) * p[i] for k, i in enumerate(order)]))
        np.testing.assert_allclose(adjusted[order], expected)
        stop = next((k for k, i in enumerate(order) if p[i] >= 0.05 / (m - k)), m)
        assert set(np.flatnonzero(adjusted < 0.05)) == set(order[:stop].tolist())
        assert np.all(adjusted >= p)


def test_too_few_seeds_get_no_verdict_and_replication_needs_both() -> None:
    """Five seeds that all agree cannot reach 5 % two-sided (2/32): no verdict below MIN_SEEDS, whatever the effect;
    a claim stands only where the fresh seeds say it again."""
    big = paired_difference([10.0, 11.0, 12.0, 13.0, 14.0], [0.0] * 5)
    assert MIN_SEEDS == 6 and signed_rank_p(np.arange(1.0, 6.0)) == pytest.approx(2 / 32)
    assert verdict(big, 'higher', 0.0) == NO_VERDICT
    assert replicated('holds', 'holds') == 'holds' and replicated('reversed', 'reversed') == 'reversed'
    assert replicated('holds', NOT_SHOWN) == NOT_REPLICATED == replicated('holds', 'reversed')
    assert replicated(NOT_SHOWN, 'holds') == NOT_SHOWN  # a claim not found is not found by replicating
    assert replicated('holds', NO_VERDICT) == NO_VERDICT
    assert relative(-0.5, [2.0, 2.0]) == -0.25 and np.isnan(relative(1.0, [1.0, -1.0]))


def test_a_family_is_adjusted_over_its_members_with_enough_seeds() -> None:
    """A cell with too few seeds gets no p-value and does not count among the m of Holm's adjustment."""
    from vtube_planning.studies.stats import family_adjusted

    enough, few = Estimate(1.0, 0.5, 1.5, 10), Estimate(1.0, 0.5, 1.5, 4)
    adjusted = family_adjusted([enough, few, enough], [0.01, 0.001, 0.04], [10, 4, 10])
    assert adjusted[0] == pytest.approx(0.02) and np.isnan(adjusted[1]) and adjusted[2] == pytest.approx(0.04)


def test_a_family_its_seeds_could_never_make_significant_gets_no_verdict() -> None:
    """Ten seeds that all agree give p = 2/1024 each: Holm over 20 cells keeps them below 5 % (0.039), over 36 cells
    no member can get there (0.070) whatever the effects, so the family gets no verdict rather than 'not shown'."""
    from vtube_planning.studies.stats import family_adjusted, smallest_p

    rng = np.random.default_rng(9)
    differences = [rng.uniform(1.0, 2.0, 10) for _ in range(36)]
    estimates = [paired_difference(d, np.zeros(10)) for d in differences]
    p = [signed_rank_p(d) for d in differences]
    assert smallest_p(10) == pytest.approx(2 / 1024) == p[0] and smallest_p(51) == 0.0
    twenty = family_adjusted(estimates[:20], p[:20], [10] * 20)
    assert all(a == pytest.approx(20 * 2 / 1024) for a in twenty)
    assert {verdict(e, 'higher', a) for e, a in zip(estimates[:20], twenty, strict=True)} == {'holds'}
    thirty_six = family_adjusted(estimates, p, [10] * 36)
    assert all(np.isnan(thirty_six)) and {
        verdict(e, 'higher', a) for e, a in zip(estimates, thirty_six, strict=True)
    } == {NO_VERDICT}
    mixed = [*estimates[:35], paired_difference(rng.uniform(1.0, 2.0, 60), np.zeros(60))]  # one member could
    assert not np.isnan(family_adjusted(mixed, [*p[:35], 1e-9], [*[10] * 35, 60])[35])


def test_the_no_verdict_rule_counts_only_the_non_zero_differences() -> None:
    """The test drops zero differences, so ten seeds of which four tie (zero difference) can give no smaller p than
    six seeds: 2/64 = 0.031. One such cell alone can hold; two cannot (2 * 0.031 >= 0.05): no verdict, where counting
    the ten seeds would have allowed 2 * 2/1024."""
    from vtube_planning.studies.stats import family_adjusted

    d = np.array([0.0, 0.0, 0.0, 0.0, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0])
    e, p = paired_difference(d, np.zeros(10)), signed_rank_p(d)
    assert nonzero_count(d) == 6 and p == pytest.approx(2 / 64)
    assert family_adjusted([e], [p], [nonzero_count(d)]) == [pytest.approx(2 / 64)]
    assert all(np.isnan(family_adjusted([e, e], [p, p], [nonzero_count(d)] * 2)))
    assert not np.isnan(family_adjusted([e, e], [p, p], [10, 10])[0])  # what counting the zeros would have let by


def test_the_critical_sum_against_the_enumerated_null_distribution() -> None:
    """The smallest sum of positive ranks whose two-sided p-value is below the level: brute force over the 2**n
    sign assignments, and signed_rank_p agrees on both sides of it."""
    import itertools

    for n in (6, 8, 10, 12):
        sums = np.array([np.dot(s, np.arange(1, n + 1)) for s in itertools.product([0, 1], repeat=n)])
        total = n * (n + 1) // 2
        for level in (0.05, 0.01, 0.05 / 6):
            p = {t: np.mean(np.abs(sums - total / 2) >= abs(t - total / 2)) for t in range(total + 1)}
            upper = [t for t in range(total + 1) if 2 * t > total and p[t] < level]
            k = critical_sum(n, level)
            assert k == (upper[0] if upper else None)
            if k is not None:  # ranks 1..n all positive but the smallest ones: sums k and k - 1
                ranks = np.arange(1.0, n + 1)
                assert signed_rank_p(_with_sum(ranks, k)) < level <= signed_rank_p(_with_sum(ranks, k - 1))
    assert critical_sum(5, 0.05) is None and critical_sum(10, 0.05 / 24) == 55  # only all ten positive: 2/1024


def _with_sum(ranks: np.ndarray, target: int) -> np.ndarray:
    """Differences with magnitudes ``ranks`` whose positive ones sum to ``target`` (greedy from the largest)."""
    signs, left = -np.ones_like(ranks), target
    for k in range(ranks.size - 1, -1, -1):
        if ranks[k] <= left:
            signs[k], left = 1.0, left - ranks[k]
    assert left == 0
    return signs * ranks


def test_the_detectable_shift_where_only_unanimous_seeds_can_hold_is_exact() -> None:
    """Where the test holds only if every one of n differences is positive (10 seeds, Holm over 24 cells), the
    power at shift s is Phi(s)**n, so the shift found with 80 % power is Phi^-1(0.8 ** (1 / n)): 2.01 SD."""
    from scipy import stats as scipy_stats

    exact = float(scipy_stats.norm.ppf(0.8 ** (1 / 10)))
    assert detectable_shift(10, family_level(24)) == pytest.approx(exact, abs=0.02)
    assert np.isinf(detectable_shift(5, 0.05)) and family_level(24) == pytest.approx(0.05 / 24)


@pytest.mark.parametrize(('n', 'size'), [(8, 1), (20, 6), (20, 24)])
def test_the_detectable_shift_is_found_with_80_percent_power_by_an_independent_monte_carlo(n: int, size: int) -> None:
    """Fresh normal samples (another seed) shifted by the detectable shift: scipy's exact signed-rank test below the
    family's level, on the shift's side, in 80 % of them (3 standard errors); 0.25 SD less, clearly fewer."""
    from scipy import stats as scipy_stats

    level, shift = family_level(size), detectable_shift(n, family_level(size))
    rng = np.random.default_rng(12345)
    draws = 1000

    def power(s: float) -> float:
        z = rng.standard_normal((draws, n)) + s
        found = (scipy_stats.wilcoxon(z, axis=1, method='exact').pvalue < level) & (np.median(z, axis=1) > 0)
        return float(np.mean(found))  # the test of each sample (row) on its own: scipy's axis, not a loop

    assert power(shift) == pytest.approx(0.8, abs=3 * np.sqrt(0.8 * 0.2 / draws))
    assert power(shift - 0.25) < 0.7


def test_the_detectable_shift_beyond_the_exact_range_follows_the_normal_approximation() -> None:
    """Above 50 differences the test is the normal approximation; the shift then nears the asymptotic one,
    (z_(1-level/2) + z_0.8) / sqrt(n * 3 / pi) (the signed-rank test's efficiency 3 / pi against the t-test)."""
    from scipy import stats as scipy_stats

    n, level = 55, 0.05
    asymptotic = (scipy_stats.norm.isf(level / 2) + scipy_stats.norm.ppf(0.8)) / np.sqrt(n * 3 / np.pi)
    assert detectable_shift(n, level) == pytest.approx(asymptotic, rel=0.05)
