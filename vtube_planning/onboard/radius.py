"""The avoidance radius r_a,i of every robot, after (a3): driven by the measured density, increase only, capped
(A9), optionally floored by the feed-forward 1/sqrt(rho*) - r_s (``docs/theory.md`` §2.8)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from vtube_planning.onboard.params import StepParams

FloatArray = NDArray[np.float64]


def avoidance_radius_rate(rho_measured: float, rho_planned: ArrayLike, params: StepParams) -> FloatArray:
    """(a3): r_a,i' = k_ra max(0, rho_r - rho*(l_i)), m/s, (N,)."""
    return params.k_ra_m3ps * np.maximum(0.0, rho_measured - np.asarray(rho_planned, dtype=float))


def feedforward_radius(rho_planned: ArrayLike, params: StepParams) -> FloatArray:
    """1/sqrt(rho*) - r_s: the avoidance radius whose lattice (spacing r_s + r_a) has density rho*, (N,)."""
    radius: FloatArray = 1.0 / np.sqrt(np.asarray(rho_planned, dtype=float)) - params.r_s_m
    return radius


def next_radius(
    r_a: FloatArray, rho_measured: float, rho_planned: FloatArray, params: StepParams, dt_s: float
) -> FloatArray:
    """r_a after one period of (a3), capped at r_a_max, floored by the feed-forward when it is on."""
    r_a = np.minimum(params.r_a_max_m, r_a + dt_s * avoidance_radius_rate(rho_measured, rho_planned, params))
    if params.feedforward:
        r_a = np.maximum(r_a, np.minimum(params.r_a_max_m, feedforward_radius(rho_planned, params)))
    return r_a
