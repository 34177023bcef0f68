"""Uncertainty of the study's numbers: bootstrap intervals, paired tests corrected for many cells, replication.

A study cell (scene, mode, swarm size, robot model) has one value per seed. Its mean gets a 95 % bootstrap interval
(scipy's BCa, percentile for quantiles). Two modes flown from the same seeds are compared *paired*: the mean of the
per-seed differences, which removes what the seed does to both (the initial formation's jitter), with its interval,
and the two-sided Wilcoxon signed-rank test of those differences (exact for small samples, no assumption of
normality). A report compares the same two modes in many cells, so the p-values of one comparison and metric over
the cells are adjusted by Holm's step-down method (which holds the chance of any false claim among them at ALPHA
whatever their dependence); which claims make one family is the report's (`vtube_planning.studies.judging`). A claim
"mode A beats mode B on a metric" holds in a cell only where the adjusted p-value is below ALPHA and the interval
excludes zero on A's side, from at least MIN_SEEDS seeds; where it does not, the effect is NOT_SHOWN, and
`detectable_shift` says how large an effect the seeds would have found (POWER), so that "not shown" is not read as
"absent". Fresh seeds held out to confirm the claims found test only those (`replicated`).
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from vtube_planning.errors import ParamsError

CONFIDENCE = 0.95
RESAMPLES = 4999
ALPHA = 0.05
"""The chance of any false claim among one comparison's cells (family-wise, after Holm's adjustment)."""
MIN_SEEDS = 6
"""Paired seeds below which no verdict is called: the exact two-sided signed-rank test cannot go below 2 / 2**n, which
is 0.0625 for five seeds, so with fewer than six no difference, however large, is significant at ALPHA."""
EXACT_UP_TO = 50
"""Differences up to which the signed-rank p-value is exact (counts below 2**50 stay exact in int64)."""
NO_VERDICT = 'no verdict'
NOT_REPLICATED = 'not replicated'
NOT_SHOWN = 'not shown'
"""The verdict where a and b could not be told apart: no evidence either way, not evidence of no effect."""
POWER = 0.8
"""The chance at which `detectable_shift` finds an effect."""
POWER_DRAWS = 20000
"""Normal samples `detectable_shift` draws (seed 0): its shift is within about 0.01 SD of the exact one."""


@dataclass(frozen=True)
class Estimate:
    """A statistic of n values and its bootstrap interval [low, high] at ``CONFIDENCE``."""

    value: float
    low: float
    high: float
    n: int

    def excludes_zero(self) -> bool:
        return self.low > 0.0 or self.high < 0.0

    def text(self, digits: int = 3) -> str:
        return f'{self.value:.{digits}f} [{self.low:.{digits}f}, {self.high:.{digits}f}]'


def mean_interval(values: ArrayLike, *, seed: int = 0) -> Estimate:
    """The mean and its BCa bootstrap interval."""
    return _bootstrap(_values(values), np.mean, 'BCa', seed)


def quantile_interval(values: ArrayLike, q: float, *, seed: int = 0) -> Estimate:
    """The q-quantile (0 < q < 1) and its percentile bootstrap interval (BCa is unreliable for quantiles)."""
    if not 0.0 < q < 1.0:
        msg = f'quantile q must lie strictly between 0 and 1; got {q!r}.'
        raise ParamsError(msg)
    return _bootstrap(_values(values), lambda x, axis: np.quantile(x, q, axis=axis), 'percentile', seed)


def paired_difference(a: ArrayLike, b: ArrayLike, *, seed: int = 0) -> Estimate:
    """Mean of a_k - b_k over matched runs (same seed, same order) and its BCa interval."""
    a, b = _values(a), _values(b)
    if a.shape != b.shape:
        msg = f'paired values need one of each per seed; got {a.size} and {b.size} values.'
        raise ParamsError(msg)
    return mean_interval(a - b, seed=seed)


def signed_rank_p(differences: ArrayLike) -> float:
    """Two-sided p-value of the Wilcoxon signed-rank test that the paired differences are centred on zero (zeros
    left out, as Wilcoxon's; 1.0 when every difference is zero): the share of the 2**n sign assignments whose
    signed-rank sum lies at least as far from its centre as the observed one, exact up to EXACT_UP_TO differences,
    ties (mid-ranks) included; the normal approximation above. scipy's own exact test covers samples without ties
    only, and with ties falls back to a permutation test that is slow and, above 13 differences, random."""
    from scipy import stats  # here, not at import: scipy.stats takes about half a second to import

    d = np.asarray(differences, dtype=float).ravel()
    d = d[d != 0.0]
    if d.size == 0:
        return 1.0
    if d.size > EXACT_UP_TO:
        return float(stats.wilcoxon(d, zero_method='wilcox', method='asymptotic').pvalue)
    doubled = np.rint(2.0 * stats.rankdata(np.abs(d))).astype(np.int64)  # mid-ranks are halves: twice is whole
    total = int(doubled.sum())
    counts = np.zeros(total + 1, dtype=np.int64)  # counts[s]: sign assignments whose positive ranks sum to s / 2
    counts[0] = 1
    for w in doubled:
        counts[w:] = counts[w:] + counts[:-w].copy()
    observed = int(doubled[d > 0].sum())
    far = np.abs(2 * np.arange(total + 1) - total) >= abs(2 * observed - total)
    return float(counts[far].sum() / 2.0**d.size)


def holm(p_values: Sequence[float]) -> NDArray[np.float64]:
    """Holm's step-down adjustment of a family of p-values: the k-th smallest times (m - k + 1), made non-decreasing
    in that order and at most 1; a claim holds where its adjusted p-value is below ALPHA."""
    p = np.asarray(p_values, dtype=float)
    order = np.argsort(p, kind='stable')
    scaled = np.minimum(1.0, np.maximum.accumulate(p[order] * (p.size - np.arange(p.size))))
    adjusted = np.empty_like(p)
    adjusted[order] = scaled
    return adjusted


def smallest_p(n: int) -> float:
    """The smallest two-sided p-value `signed_rank_p` can give from n non-zero paired differences: 2 / 2**n where
    the test is exact (every difference of one sign), none (0) where the normal approximation takes over."""
    return 2.0 / 2.0**n if n <= EXACT_UP_TO else 0.0


def nonzero_count(differences: ArrayLike) -> int:
    """How many paired differences `signed_rank_p` uses: the non-zero ones (Wilcoxon's rule drops the zeros)."""
    return int(np.count_nonzero(np.asarray(differences, dtype=float)))


def family_adjusted(estimates: Sequence[Estimate], p_values: Sequence[float], nonzero: Sequence[int]) -> list[float]:
    """`holm` over the members of a family (one claim's cells or measures) that have MIN_SEEDS differences or
    more; NaN for the others, which get no verdict. NaN for every member too where none could be significant: Holm
    multiplies the smallest p-value by the family's size m, so where m * 2 / 2**n is at or above ALPHA for every
    member, n its ``nonzero`` differences (the test drops the zeros), no claim can hold, however large the effects;
    the family then gets no verdict (more seeds, or a smaller family), not a "not shown" that its seeds could never
    have escaped."""
    enough = [k for k, e in enumerate(estimates) if e.n >= MIN_SEEDS]
    adjusted = [math.nan] * len(estimates)
    if not enough or len(enough) * min(smallest_p(nonzero[k]) for k in enough) >= ALPHA:
        return adjusted
    for k, p in zip(enough, holm([p_values[k] for k in enough]), strict=True):
        adjusted[k] = float(p)
    return adjusted


def family_level(size: int) -> float:
    """The level a family of ``size`` claims holds its strongest member to (Holm's first step, ALPHA / size): the
    level at which one true effect among them must be found, whatever the others."""
    return ALPHA / max(size, 1)


def critical_sum(n: int, level: float) -> int | None:
    """The smallest sum of positive ranks (1..n, no ties) at which the two-sided signed-rank test of n differences
    gives p < ``level`` on the positive side (the test of `signed_rank_p`: exact up to EXACT_UP_TO, the normal
    approximation above); None where no outcome reaches it."""
    total = n * (n + 1) // 2
    if n > EXACT_UP_TO:
        from scipy import stats  # here, not at import: scipy.stats takes about half a second to import

        mean, sd = total / 2.0, math.sqrt(n * (n + 1) * (2 * n + 1) / 24.0)
        k = math.floor(mean + sd * float(stats.norm.isf(level / 2.0))) + 1
        return k if k <= total else None
    counts = np.zeros(total + 1)
    counts[0] = 1.0
    for rank in range(1, n + 1):
        counts[rank:] = counts[rank:] + counts[:-rank].copy()
    tail = np.cumsum(counts[::-1])[::-1] / 2.0**n  # tail[t]: the chance of a sum >= t
    p = np.minimum(1.0, 2.0 * tail)
    upper = [t for t in range(total + 1) if 2 * t > total and p[t] < level]
    return upper[0] if upper else None


@functools.lru_cache(maxsize=256)
def detectable_shift(n: int, level: float) -> float:
    """The smallest shift of the paired differences' mean, in units of their standard deviation, that the
    signed-rank test of n differences at ``level`` finds (p < level, on the shift's side) with probability POWER,
    the differences drawn normal; inf where no outcome of n differences reaches ``level``.

    By Monte Carlo with a fixed seed: the sum of positive ranks is the number of positive Walsh averages
    (z_i + z_j) / 2 + shift, i <= j, so it reaches `critical_sum` k exactly when the shift exceeds minus the k-th
    largest Walsh average of z; the shift found with probability POWER is the POWER-quantile of that threshold
    over POWER_DRAWS samples z (the same draws for every shift, so no search is needed)."""
    k = critical_sum(n, level)
    if k is None:
        return math.inf
    draws = np.random.default_rng(0).standard_normal((POWER_DRAWS, n))
    i, j = np.triu_indices(n)
    thresholds = []
    for chunk in np.array_split(draws, max(1, POWER_DRAWS * i.size // 2_000_000)):
        walsh = (chunk[:, i] + chunk[:, j]) / 2.0
        thresholds.append(np.partition(walsh, walsh.shape[1] - k, axis=1)[:, walsh.shape[1] - k])
    return float(np.quantile(-np.concatenate(thresholds), POWER))


def verdict(difference: Estimate, better: str, p_adjusted: float) -> str:
    """'holds', NOT_SHOWN or 'reversed' for a claim that a - b is ``better`` (``'higher'``, say minimum
    distance, or ``'lower'``: passing time, collisions): significant where the adjusted p-value is below ALPHA and
    the interval excludes zero; NO_VERDICT from fewer than MIN_SEEDS differences, or without an adjusted p-value
    (NaN: `family_adjusted` found that no member of its family could be significant)."""
    if better not in ('higher', 'lower'):
        msg = f"better must be 'higher' or 'lower'; got {better!r}."
        raise ParamsError(msg)
    if difference.n < MIN_SEEDS or math.isnan(p_adjusted):
        return NO_VERDICT
    if not (difference.excludes_zero() and p_adjusted < ALPHA):
        return NOT_SHOWN
    sign = 1.0 if better == 'higher' else -1.0
    return 'holds' if sign * difference.value > 0 else 'reversed'


def replicated(discovery: str, confirmation: str) -> str:
    """A claim's verdict from the seeds it was found on and fresh seeds held out to confirm it: a claim (or its
    reversal) stands only where both say so; NOT_REPLICATED where the fresh seeds do not."""
    if NO_VERDICT in (discovery, confirmation):
        return NO_VERDICT
    if discovery in ('holds', 'reversed'):
        return discovery if confirmation == discovery else NOT_REPLICATED
    return discovery


def relative(difference: float, reference: ArrayLike) -> float:
    """A difference as a share of the reference's mean magnitude (the effect size printed beside the interval);
    NaN when that mean is zero."""
    scale = abs(float(np.mean(np.asarray(reference, dtype=float))))
    return difference / scale if scale > 0.0 else math.nan


def _values(values: ArrayLike) -> NDArray[np.float64]:
    x = np.asarray(values, dtype=float).ravel()
    if x.size < 2 or not np.all(np.isfinite(x)):
        msg = f'an interval needs at least two finite values (one per seed); got {x.tolist()}.'
        raise ParamsError(msg)
    return x


def _bootstrap(x: NDArray[np.float64], statistic: Callable[..., Any], method: str, seed: int) -> Estimate:
    from scipy import stats  # here, not at import: scipy.stats takes about half a second to import

    value = float(np.asarray(statistic(x, axis=-1)))
    if np.ptp(x) == 0.0:  # every seed gave the same value: nothing to resample
        return Estimate(value, value, value, x.size)
    for how in (method, 'percentile'):  # BCa is undefined on near-degenerate samples: percentile then
        with warnings.catch_warnings():
            warnings.simplefilter('ignore')  # scipy warns before returning NaN for an undefined BCa interval
            result = stats.bootstrap(
                (x,),
                statistic,
                confidence_level=CONFIDENCE,
                n_resamples=RESAMPLES,
                method=how,
                random_state=np.random.default_rng(seed),
            )
        low, high = result.confidence_interval
        if np.isfinite(low) and np.isfinite(high):
            break
    return Estimate(value, float(low), float(high), x.size)


def cell_values(rows: Sequence[dict[str, Any]], metric: str, **where: Any) -> NDArray[np.float64]:
    """The metric's values of the rows matching ``where`` (column = value), ordered by seed."""
    chosen = sorted((r for r in rows if all(r.get(k) == v for k, v in where.items())), key=lambda r: int(r['seed']))
    return np.array([float(r[metric]) for r in chosen])
