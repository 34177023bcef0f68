"""Bootstrap intervals and paired differences on synthetic data whose answer is known."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.errors import ParamsError
from vtube_planning.stats import (
    Estimate,
    cell_values,
    mean_interval,
    paired_difference,
    quantile_interval,
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
    assert verdict(paired, 'higher') == 'holds' and verdict(paired, 'lower') == 'reversed'
    unpaired_a, unpaired_b = mean_interval(a), mean_interval(b)
    assert unpaired_a.low < unpaired_b.high  # the unpaired intervals overlap: they could not tell


def test_no_difference_does_not_hold() -> None:
    rng = np.random.default_rng(4)
    same = paired_difference(rng.normal(0.0, 1.0, 12), rng.normal(0.0, 1.0, 12))
    assert same.low < 0.0 < same.high and verdict(same, 'higher') == 'does not hold'


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
