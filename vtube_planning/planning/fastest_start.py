"""The fastest admissible profile: where the convex-concave procedure starts, near the optimum."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from vtube_planning.planning.problem import Problem, fastest_expansion

FloatArray = NDArray[np.float64]

REPAIRS = 20
"""Passes that slow the fastest admissible profile where (p7) needs it, before the slowest start is used instead."""


def fastest_admissible(problem: Problem) -> tuple[FloatArray, FloatArray] | None:
    """A start near the optimum for the convex-concave procedure, or None where it cannot be had.

    The fastest speed profile that (p2)-(p4) admit, as in time-optimal path parameterisation: from v_0, accelerate
    at a_v up to the caps, and brake at a_v in time for each; with the density falling along it as fast as (p6)
    allows. Where that is too fast for the local-width (p7), w >= ratio max(rho) / (a_rho dl_p), the speed cap is
    lowered to what (p7) asks and the profile recomputed, for at most ``REPAIRS`` passes. Every constraint then
    holds, so the procedure may start there. The rigid-shift (p7) is not checked here: it starts from the slowest
    profile, as do the room for braking and a problem whose repairs do not settle.
    """
    swarm, options = problem.swarm, problem.options
    if options.predictive_model == 'rigid_shift' or options.braking_room:
        return None
    dl = problem.dl_m
    floor = 1.0 / problem.speed_cap_mps
    for _ in range(REPAIRS):
        w = _fastest_slowness(floor, 1.0 / problem.v0_mps, swarm.a_v_mps2 * dl)
        if w is None or w.max() > 1.0 / swarm.v_min_mps:
            return None
        rho = fastest_expansion(swarm, problem.rho0_per_m2, w, dl)
        if options.predictive_model == 'none':
            return w, rho
        need = problem.width_ratio * np.maximum(rho[:-1], rho[1:]) / (swarm.a_rho * options.lookahead_m)
        short = need > np.minimum(w[:-1], w[1:])
        if not short.any():
            return w, rho
        floor[:-1][short] = np.maximum(floor[:-1][short], need[short])
        floor[1:][short] = np.maximum(floor[1:][short], need[short])
    return None


def _least_slowness(target: float, c: float) -> float:
    """The root of x + c x^3 = ``target`` in (0, target] (Newton from ``target``)."""
    x = target
    for _ in range(50):
        step = (x + c * x**3 - target) / (1.0 + 3.0 * c * x**2)
        x -= step
        if abs(step) <= 1e-15 * x:
            break
    return x


def _fastest_slowness(floor: FloatArray, w0: float, rate: FloatArray) -> FloatArray | None:
    """The least slowness profile with w >= ``floor``, w_0 = ``w0`` and (p3) exact: w_k - w_{k+1} <= rate_k w_{k+1}^3
    (speeding up) and w_{k+1} - w_k <= rate_k w_k^3 (slowing down), rate = a_v dl; None when w_0 cannot brake in
    time for the floor ahead."""
    w = [float(v) for v in floor]
    rates = [float(c) for c in rate]
    w[0] = w0
    for k, c in enumerate(rates):  # accelerate as hard as (p3) allows
        w[k + 1] = max(w[k + 1], _least_slowness(w[k], c))
    for k in range(len(rates) - 1, -1, -1):  # brake in time for what lies ahead
        need = _least_slowness(w[k + 1], c=rates[k])
        if k == 0 and need > w0 * (1.0 + 1e-12):
            return None
        w[k] = max(w[k], need) if k else w0
    return np.array(w)
