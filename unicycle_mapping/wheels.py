"""Differential-drive limits: wheel speeds, curvature-preserving scaling, the always-realisable speed."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from unicycle_mapping.errors import as_columns, positive

FloatArray = NDArray[np.float64]


WHEEL_LIMIT_SHARE = 1.0 - 1e-9
"""Commands are scaled to this share of the wheel limit, not to the limit itself: a wheel scaled to the limit
exactly is recomputed by the testbed's verifier (the same formula) up to 2e-15 rad/s over it, and counted (one step
of a twenty-robot run on the curve, ``docs/howto/submitting.md``)."""


def wheel_speeds(dxu: ArrayLike, axle_length_m: float, wheel_radius_m: float) -> FloatArray:
    """Left and right wheel speeds (2v -/+ L omega) / (2 r) in rad/s, (2, N), for commands [v; omega] (2, N)."""
    dxu = as_columns(dxu, 2, 'unicycle commands dxu')
    length = positive(axle_length_m, 'axle_length_m')
    radius = positive(wheel_radius_m, 'wheel_radius_m')
    return np.vstack([2 * dxu[0] - length * dxu[1], 2 * dxu[0] + length * dxu[1]]) / (2 * radius)


def scale_to_wheel_limits(
    dxu: ArrayLike, axle_length_m: float, wheel_radius_m: float, max_wheel_speed_radps: float
) -> tuple[FloatArray, FloatArray]:
    """Scale each robot's [v; omega] uniformly so both wheels stay within the limit.

    Unlike the testbed's per-wheel clipping, a common factor keeps the curvature omega / v, so the robot still
    drives along the intended arc, only slower. A scaled robot's faster wheel turns at `WHEEL_LIMIT_SHARE` of the
    limit, so that no rounding puts it over.

    Returns
    -------
    dxu
        The scaled commands, (2, N).
    scale
        The factor applied to each robot, in (0, 1], (N,).
    """
    dxu = as_columns(dxu, 2, 'unicycle commands dxu')
    limit = positive(max_wheel_speed_radps, 'max_wheel_speed_radps') * WHEEL_LIMIT_SHARE
    largest = np.abs(wheel_speeds(dxu, axle_length_m, wheel_radius_m)).max(axis=0)
    scale = np.where(largest > limit, limit / np.where(largest > 0, largest, 1.0), 1.0)
    return dxu * scale, scale


def max_realisable_si_speed(
    d: float, axle_length_m: float, wheel_radius_m: float, max_wheel_speed_radps: float
) -> float:
    """Largest single-integrator speed that is realisable in every direction without saturating a wheel.

    For a speed s at angle alpha to the heading, v = s cos(alpha) and omega = s sin(alpha) / d; the wheels stay
    within r phi_max when s (|cos alpha| + (L / 2d) |sin alpha|) <= r phi_max, whose worst case over alpha gives
    s = r phi_max / sqrt(1 + (L / 2d)^2) (``docs/robotarium.md`` §8.4).
    """
    d = positive(d, 'projection distance d')
    ratio = positive(axle_length_m, 'axle_length_m') / (2 * d)
    return (
        positive(wheel_radius_m, 'wheel_radius_m')
        * positive(max_wheel_speed_radps, 'max_wheel_speed_radps')
        / (math.sqrt(1 + ratio**2))
    )
