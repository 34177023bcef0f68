"""Density tracking along the tube (not in the paper; ``docs/theory.md`` §2.9): the forward speeds spread over the
swarm's length by its relative density error, so that a swarm denser than the plan lengthens and a sparser one
closes up."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def stretched_speed(
    forward_mps: FloatArray,
    l_m: FloatArray,
    swarm_l_m: FloatArray,
    rho_measured: float,
    rho_planned: float,
    gain_mps: float,
    band_mps: tuple[float, float],
) -> FloatArray:
    """The forward speeds v*_i + g e s_i within the speed band ``band_mps`` (v_min, v_max), (N,).

    e = clip((rho_r - rho*) / rho*, -1, 1) is the swarm's relative density error at its centre (``rho_planned``,
    rho* at the swarm centre's arc length); s_i = clip((l_i - l_c) / h, -1, 1) places robot i along the swarm, l_c
    the mean arc length of the swarm's robots ``swarm_l_m`` and h their largest distance from it (a swarm of one
    spot does not stretch). A robot ahead of the centre goes faster by up to g, one behind it slower.
    """
    center = float(swarm_l_m.mean())
    half = float(np.abs(swarm_l_m - center).max())
    if gain_mps == 0.0 or half <= 0.0:
        return forward_mps
    error = float(np.clip((rho_measured - rho_planned) / rho_planned, -1.0, 1.0))
    place = np.clip((l_m - center) / half, -1.0, 1.0)
    speed: FloatArray = np.clip(forward_mps + gain_mps * error * place, *band_mps)
    return speed
