"""The regularity conditions of a virtual tube (``docs/theory.md`` §3.2), checked on a dense grid of arc lengths.

lambda |kappa| < 1 (R2), no two distant cross-sections intersect (R3), lambda is C^1 (R4); each failure is a
[`TubeError`][vtube_planning.errors.TubeError] naming the arc length. lambda > 0 holds by construction: every width
part is monotone between positive values, which [`WidthProfile`][vtube_planning.geometry.width.WidthProfile] checks.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from vtube_planning.errors import TubeError
from vtube_planning.geometry.centerline import CenterCurve
from vtube_planning.geometry.width import WidthProfile

FloatArray = NDArray[np.float64]

SLOPE_JUMP_TOL = 1e-9
"""Largest jump of d lambda / dl at a breakpoint still accepted as C^1."""
_LEFT = np.array([-1.0, 1.0])
"""(t_x, t_y) reversed times this is the left normal (-t_y, t_x)."""


def check_grid(center: CenterCurve, width: WidthProfile, samples: FloatArray) -> FloatArray:
    """Dense arc lengths for the regularity checks: 4x the density of ``samples`` (from 0 to L), and both sides of
    every breakpoint."""
    length = center.length_m
    fine = np.linspace(0.0, length, 4 * (samples.size - 1) + 1)
    breaks = np.concatenate([center.breakpoints, width.breakpoints])
    eps = 1e-9 * max(1.0, length)
    grid = np.concatenate([fine, breaks, breaks - eps, breaks + eps])
    checked: FloatArray = np.unique(np.clip(grid, 0.0, length))
    return checked


def check_regularity(center: CenterCurve, width: WidthProfile, samples: FloatArray, name: str) -> None:
    """[`TubeError`][vtube_planning.errors.TubeError] unless the tube named ``name`` (empty: unnamed) is regular;
    ``samples`` are its projection's sample arc lengths."""
    label = f'tube {name!r}' if name else 'tube'
    length = center.length_m
    for l_knot, jump_value, jump_slope in width.continuity_defects():
        if abs(jump_value) > SLOPE_JUMP_TOL * max(1.0, length) or abs(jump_slope) > SLOPE_JUMP_TOL:
            msg = (
                f'{label}: the half-width is not C^1 at l = {l_knot:.3f} m (slope jumps by {jump_slope:+.4g}); '
                'use a smooth part or give the linear part a corner blend corner_m > 0.'
            )
            raise TubeError(msg)
    grid = check_grid(center, width, samples)
    lam = width.value(grid)
    kappa = center.frame(grid)[2]
    fold = lam * np.abs(kappa)
    if np.any(fold >= 1.0):
        k = int(np.argmax(fold >= 1.0))
        msg = (
            f'{label} is over-curved at l = {grid[k]:.3f} m: half-width {lam[k]:.4g} m is not below the curvature '
            f'radius {1.0 / abs(kappa[k]):.4g} m (lambda |kappa| = {fold[k]:.3f} >= 1), so cross-sections fold; '
            'narrow the tube there or increase the turn radius.'
        )
        raise TubeError(msg)
    _check_cross_sections(center, width, samples, label)


def _check_cross_sections(center: CenterCurve, width: WidthProfile, grid: FloatArray, label: str) -> None:
    """R3: no two cross-sections (segments gamma -/+ lambda n) at the arc lengths ``grid`` intersect."""
    pos, tan, _ = center.frame(grid)
    lam = width.value(grid)
    left = tan[:, ::-1] * _LEFT
    ends_a = pos - lam[:, None] * left
    ends_b = pos + lam[:, None] * left
    pairs = cKDTree(pos).query_pairs(2.0 * float(lam.max()), output_type='ndarray')
    if pairs.size == 0:
        return
    i, j = pairs[:, 0], pairs[:, 1]

    def side(a: FloatArray, b: FloatArray, c: FloatArray) -> FloatArray:
        turn: FloatArray = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
        return turn

    crossing = (side(ends_a[i], ends_b[i], ends_a[j]) * side(ends_a[i], ends_b[i], ends_b[j]) < 0.0) & (
        side(ends_a[j], ends_b[j], ends_a[i]) * side(ends_a[j], ends_b[j], ends_b[i]) < 0.0
    )
    if np.any(crossing):
        k = int(np.argmax(crossing))
        la, lb = sorted((grid[i[k]], grid[j[k]]))
        msg = (
            f'{label} overlaps itself: the cross-sections at l = {la:.3f} m and l = {lb:.3f} m intersect; '
            'move these parts of the centre line apart or make the tube narrower there.'
        )
        raise TubeError(msg)
