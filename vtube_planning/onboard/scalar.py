"""The law's scalar building blocks (``docs/theory.md`` §2.3-2.4): the step sigma, the smooth saturation s, the
barrier gain -dV/dx, and the speed band's radial saturations."""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

BARRIER_EPS = 1e-6
"""epsilon_m = epsilon_t = epsilon_s of the barrier functions (the group's code, ``docs/theory.md`` §2.5)."""


def sigma(x: ArrayLike, d1: ArrayLike, d2: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The C^1 cubic step sigma(x, d1, d2): 1 for x <= d1, 0 for x >= d2; returns (value, d/dx).

    Shapes broadcast. In place and in few array operations: the step calls it every period, on a handful of robots
    or on the hundreds of thousands of pairs of a large swarm.
    """
    x = np.asarray(x, dtype=float)
    band: FloatArray = np.asarray(d2, dtype=float) - np.asarray(d1, dtype=float)
    t: FloatArray = np.divide(x - d1, band)
    np.maximum(t, 0.0, out=t)  # np.clip(t, 0, 1)'s values, without its call cost
    np.minimum(t, 1.0, out=t)
    value = 2.0 * t  # 1 - t t (3 - 2 t)
    np.subtract(3.0, value, out=value)
    value *= t * t
    np.subtract(1.0, value, out=value)
    slope = -6.0 * t  # -6 t (1 - t) / band: (-)0 outside (d1, d2), where t is clipped to 0 or 1
    np.subtract(1.0, t, out=t)
    slope *= t
    slope /= band
    return value, slope


def smooth_saturation(x: ArrayLike, eps: float) -> tuple[FloatArray, FloatArray]:
    """The C^1 saturation s(x, eps) of ``docs/theory.md`` §2.3 (x below x1, a circular arc, then 1); (value, d/dx).

    Below x1 = x2 - eps sin 45deg (< 1) s = x, above x2 = 1 + eps / tan 67.5deg (> 1) s = 1, so ``min(x, 1)`` is
    s outside the arc; the arc (width about 0.7 eps) is evaluated only where some x falls on it.
    """
    x = np.asarray(x, dtype=float)
    x1, x2 = _saturation_corners(eps)
    value = np.minimum(x, 1.0, out=np.empty(x.shape))  # an array also for a scalar x: written below
    slope = np.array(x <= x1, dtype=float)
    arc = (x > x1) & (x < x2)
    if arc.any():
        on_arc = x[arc]
        root = np.sqrt(np.maximum(eps**2 - (on_arc - x2) ** 2, 0.0))  # > 0 inside the arc
        value[arc] = (1.0 - eps) + root
        slope[arc] = (x2 - on_arc) / root
    return value, slope


@lru_cache(maxsize=4)
def _saturation_corners(eps: float) -> tuple[float, float]:
    """x1 and x2 of s(x, eps)."""
    x2 = 1.0 + eps / math.tan(math.radians(67.5))
    return x2 - eps * math.sin(math.radians(45.0)), x2


def barrier_gain(
    x: ArrayLike, offset: FloatArray | float, d1: FloatArray | float, d2: ArrayLike, k: FloatArray | float
) -> FloatArray:
    """-dV/dx of the barrier V = k sigma(x, d1, d2) / ((1 + eps) x - offset s(x / offset, eps)), theory §2.4.

    ``offset`` is 2 r_s between robots (d1 = 2 r_s) and r_s at the wall (d1 = r_s); each of them a number or an
    array like x, element by element. Non-negative; huge (about k / (eps x^2)) inside the safety distance, zero
    beyond d2.
    """
    xs = np.maximum(np.asarray(x, dtype=float), 1e-9)
    s_val, s_slope = smooth_saturation(xs / offset, BARRIER_EPS)
    den = (1.0 + BARRIER_EPS) * xs  # (1 + eps) x - offset s
    s_val *= offset
    den -= s_val
    sig, sig_slope = sigma(xs, d1, d2)
    # -dV/dx = -k (sigma' / den - sigma ((1 + eps) - s') / den^2), in place (see sigma)
    sig_slope /= den
    np.subtract(1.0 + BARRIER_EPS, s_slope, out=s_slope)
    sig *= s_slope
    np.square(den, out=den)
    sig /= den
    sig_slope -= sig
    sig_slope *= np.negative(k)
    return np.maximum(sig_slope, 0.0, out=sig_slope)


def cap_norm(u: FloatArray, limit: ArrayLike) -> FloatArray:
    """Columns of (2, N) ``u`` rescaled to a norm of at most ``limit`` (scalar or (N,)); shorter ones unchanged."""
    speed = np.hypot(u[0], u[1])
    limit = np.asarray(limit, dtype=float)
    return u * np.where(speed > limit, limit / np.maximum(speed, 1e-300), 1.0)


def saturate(u: FloatArray, v_min: float, v_max: float, fallback: FloatArray) -> FloatArray:
    """sat(u, v_min, v_max) column-wise on (2, N): radial rescaling into [v_min, v_max]; u = 0 -> v_min fallback."""
    speed = np.hypot(u[0], u[1])
    clipped = np.minimum(np.maximum(speed, v_min), v_max)
    if speed.min() > 1e-12:  # the usual case, in fewer array operations
        clipped /= speed
        scaled: FloatArray = u * clipped
        return scaled
    zero = speed <= 1e-12
    scale = np.where(zero, 0.0, clipped / np.where(zero, 1.0, speed))
    return np.where(zero, v_min * fallback, u * scale)
