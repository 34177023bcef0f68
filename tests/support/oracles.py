"""Closed forms of docs/theory.md, written out independently of the package, for the tests to compare with."""

from __future__ import annotations


def sigma_published(x: float, d1: float, d2: float) -> float:
    """docs/theory.md §2.3 with its coefficients A, B, C, D."""
    den = (d1 - d2) ** 3
    if x <= d1:
        return 1.0
    if x >= d2:
        return 0.0
    return (-2 * x**3 + 3 * (d1 + d2) * x**2 - 6 * d1 * d2 * x + d2**2 * (3 * d1 - d2)) / den
