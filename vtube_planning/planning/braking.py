"""Room for braking (``options.braking_room``): the planned spacing covers the distance a robot needs to slow to v_min.

A robot held to (2), (3) cannot stop: behind a neighbour already at v_min it closes the gap by
(v^2 - v_min^2) / (2 a_v) while it brakes from v. At density rho the swarm's lattice spacing is 1 / sqrt(rho), and
two robots are safe at 2 r_s, so the plan keeps

    1 / sqrt(rho) >= 2 r_s + (v^2 - v_min^2) / (2 a_v),   i.e.   w >= h(rho) = (v_min^2 + 2 a_v (rho^-1/2 - 2 r_s))^-1/2

on every grid interval, as min(w_k, w_k+1) >= h(max(rho_k, rho_k+1)) (the interval's fastest speed at its largest
density, as (p6) and (p7) are imposed). h is increasing and concave in rho, so the constraint is imposed, like (p3),
with h replaced by its tangent at the previous iterate, which lies above h: every iterate is feasible
(``docs/theory.md`` §8.9).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from vtube_planning.params import SwarmParams

FloatArray = NDArray[np.float64]


def densest_braking(swarm: SwarmParams) -> float:
    """The largest density at which robots at v_min keep 2 r_s apart, 1 / (2 r_s)^2, robots/m^2 (h's domain)."""
    return 1.0 / (2.0 * swarm.r_s_m) ** 2


def braking_slowness(swarm: SwarmParams, rho: FloatArray) -> FloatArray:
    """h(rho): the least slowness (s/m) from which a robot brakes to v_min within the spacing that density rho leaves
    beyond 2 r_s (1 / v_min at `densest_braking`, where none is left)."""
    room = np.asarray(rho, dtype=float) ** -0.5 - 2.0 * swarm.r_s_m
    out: FloatArray = (swarm.v_min_mps**2 + 2.0 * swarm.a_v_mps2 * room) ** -0.5
    return out


def braking_tangent(swarm: SwarmParams, rho_bar: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The tangent of h at ``rho_bar`` (clipped into h's domain) as slope and intercept: h(rho) <= slope rho +
    intercept for every rho, with equality at rho_bar (h is concave)."""
    rho = np.minimum(np.asarray(rho_bar, dtype=float), densest_braking(swarm))
    h = braking_slowness(swarm, rho)
    slope = 0.5 * swarm.a_v_mps2 * h**3 * rho**-1.5  # dh/drho = -1/2 h^3 2 a_v d(rho^-1/2)/drho
    return slope, h - slope * rho


def braking_excess(swarm: SwarmParams, speed_mps: FloatArray, density: FloatArray) -> FloatArray:
    """The relative shortfall of the spacing, per interval of a plan sampled at ``speed_mps`` and ``density``:
    (2 r_s + braking distance at the interval's fastest speed) times sqrt(its largest density), less 1 (> 0:
    the spacing does not cover the braking)."""
    v = np.maximum(speed_mps[:-1], speed_mps[1:])
    rho = np.maximum(density[:-1], density[1:])
    need = 2.0 * swarm.r_s_m + (v**2 - swarm.v_min_mps**2) / (2.0 * swarm.a_v_mps2)
    out: FloatArray = need * np.sqrt(rho) - 1.0
    return out
