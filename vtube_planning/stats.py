"""Uncertainty of the study's numbers: bootstrap intervals of a mean, of a quantile, and of paired differences.

A study cell (scene, mode, swarm size, robot model) has one value per seed. Its mean gets a 95 % bootstrap interval
(scipy's BCa, percentile for quantiles). Two modes flown from the same seeds are compared *paired*: the interval of
the mean of the per-seed differences, which removes what the seed does to both (the initial formation's jitter). A
claim "mode A beats mode B on a metric" holds only where that interval excludes zero on A's side.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from vtube_planning.errors import ParamsError

CONFIDENCE = 0.95
RESAMPLES = 4999


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


def verdict(difference: Estimate, better: str) -> str:
    """'holds', 'does not hold' (interval includes zero) or 'reversed' for a claim that a - b is ``better``.

    ``better`` is ``'higher'`` (say, minimum distance) or ``'lower'`` (passing time, collisions).
    """
    if better not in ('higher', 'lower'):
        msg = f"better must be 'higher' or 'lower'; got {better!r}."
        raise ParamsError(msg)
    if not difference.excludes_zero():
        return 'does not hold'
    sign = 1.0 if better == 'higher' else -1.0
    return 'holds' if sign * difference.value > 0 else 'reversed'


def _values(values: ArrayLike) -> NDArray[np.float64]:
    x = np.asarray(values, dtype=float).ravel()
    if x.size < 2 or not np.all(np.isfinite(x)):
        msg = f'an interval needs at least two finite values (one per seed); got {x.tolist()}.'
        raise ParamsError(msg)
    return x


def _bootstrap(x: NDArray[np.float64], statistic: Callable[..., Any], method: str, seed: int) -> Estimate:
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
