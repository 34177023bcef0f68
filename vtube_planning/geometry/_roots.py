"""Vectorised root finding: Newton's method safeguarded by bisection inside a bracket."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IndexArray = NDArray[np.intp]


def bracketed_newton(
    fun: Callable[[FloatArray, IndexArray], tuple[FloatArray, FloatArray]],
    lo: FloatArray,
    hi: FloatArray,
    x0: FloatArray,
    *,
    xtol: float,
    max_iter: int = 80,
) -> FloatArray:
    """Solve ``f_i(x_i) = 0`` for 1-D arrays, each ``f_i`` increasing with ``f_i(lo_i) <= 0 <= f_i(hi_i)``.

    Every iterate stays inside its bracket: a Newton step that leaves the bracket, or meets a non-positive
    derivative, is replaced by bisection, so convergence is guaranteed and quadratic near a simple root.

    Parameters
    ----------
    fun
        ``fun(x, idx)`` returns ``(f, f')`` of the equations ``idx`` at ``x`` (1-D arrays of equal length);
        only equations that have not converged are evaluated.
    lo, hi, x0
        Brackets and initial guesses, shape (k,), ``lo <= hi``.
    xtol
        Absolute tolerance on ``x``: an equation stops once its step is below it.
    max_iter
        Upper bound on iterations (bisection alone halves the bracket each time).

    Returns
    -------
    The roots, shape (k,).
    """
    lo = np.array(lo, dtype=float)
    hi = np.array(hi, dtype=float)
    x = np.clip(np.array(x0, dtype=float), lo, hi)
    idx = np.arange(x.size)
    for _ in range(max_iter):
        if idx.size == 0:
            break
        xa, la, ha = x[idx], lo[idx], hi[idx]
        f, df = fun(xa, idx)
        la = np.where(f <= 0.0, xa, la)
        ha = np.where(f >= 0.0, xa, ha)
        with np.errstate(divide='ignore', invalid='ignore'):
            xn = xa - f / df
        bisect = ~((df > 0.0) & (xn >= la) & (xn <= ha))
        xn = np.where(bisect, 0.5 * (la + ha), xn)
        xn = np.where(f == 0.0, xa, xn)
        x[idx], lo[idx], hi[idx] = xn, la, ha
        idx = idx[(np.abs(xn - xa) > xtol) & (ha - la > xtol)]
    roots: FloatArray = x
    return roots
