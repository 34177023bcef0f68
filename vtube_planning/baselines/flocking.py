"""The paper's baselines, run through the same simulator and metrics as the planned controller.

Optimized flocking (Vasarhelyi et al., Science Robotics 2018; ``docs/theory.md`` §6.1), from the original authors' code
(robotsim ``algo_spp_evol.c``): every robot's desired velocity is the sum of

* self-propulsion along the tube: ``v_flock t_c`` (the tube tangent as the migration direction);
* linear repulsion: ``min(p_rep (r0_rep - r_ij), v_rep)`` along ``(r_i - r_j) / r_ij`` for ``r_ij < r0_rep``;
* velocity alignment ("friction") with the braking curve D: where ``v_ij = |v_j - v_i|`` exceeds
  ``max(v_frict, D(r_ij - r0_frict, a_frict, p_frict))``, ``C_frict (v_ij - v_max_ij) (v_j - v_i) / v_ij``;
* walls through shill agents: one on each tube boundary at the robot's cross-section, moving inward at
  ``v_shill``; where ``|v_s - v_i|`` exceeds ``D(d_wall - r0_shill, a_shill, p_shill)`` the robot is pulled
  towards the shill's velocity by the excess;

capped at v_max (robotsim's CutOffMode) and, for the speed-constrained variant, floored at v_min. The paper ran it
with v_min = 0. Parameters are robotsim's ``flockingparams.dat`` scaled to the seed's geometry: lengths by
(r_s + r_a) / r0_rep, speeds by v_max / 8, rates by their ratio, accelerations by speed^2 / length.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vtube_planning._validate import is_real
from vtube_planning.errors import ParamsError
from vtube_planning.onboard import Projection
from vtube_planning.params import SwarmParams

FloatArray = NDArray[np.float64]

ROBOTSIM = {
    'v_flock': 4.0,
    'v_max': 8.0,
    'r0_rep': 25.667,
    'p_rep': 0.4,
    'v_rep': 6.197,
    'r0_frict_offset': 10.0,
    'c_frict': 0.0238,
    'v_frict': 0.5,
    'p_frict': 0.4,
    'a_frict': 2.5,
    'r0_shill': 0.0,
    'v_shill': 6.52,
    'p_shill': 0.4,
    'a_shill': 2.5,
}
"""robotsim's ``parameters/flockingparams.dat`` (``docs/theory.md`` §6.1), SI units."""


@dataclass(frozen=True)
class FlockingParams:
    """Optimized-flocking parameters (SI units); [`scaled`][vtube_planning.baselines.flocking.FlockingParams.scaled]
    builds the set used in the comparison."""

    v_flock: float
    v_max: float
    v_min: float
    r0_rep: float
    p_rep: float
    v_rep: float
    r0_frict: float
    c_frict: float
    v_frict: float
    p_frict: float
    a_frict: float
    r0_shill: float
    v_shill: float
    p_shill: float
    a_shill: float

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if not is_real(value) or value < 0:
                msg = f'flocking parameter {name} must be a finite number >= 0; got {value!r}.'
                raise ParamsError(msg)
        if self.v_min > self.v_max:
            msg = f'flocking v_min ({self.v_min}) exceeds v_max ({self.v_max}).'
            raise ParamsError(msg)

    @classmethod
    def scaled(cls, swarm: SwarmParams, *, speed_constrained: bool = False) -> FlockingParams:
        """robotsim's set scaled to the swarm: lengths x (r_s + r_a)/r0_rep, speeds x v_max/8; v_min 0 or v_min."""
        length = (swarm.r_s_m + swarm.r_a_m) / ROBOTSIM['r0_rep']
        speed = swarm.v_max_mps / ROBOTSIM['v_max']
        rate, accel = speed / length, speed**2 / length
        r = ROBOTSIM
        return cls(
            v_flock=r['v_flock'] * speed,
            v_max=swarm.v_max_mps,
            v_min=swarm.v_min_mps if speed_constrained else 0.0,
            r0_rep=r['r0_rep'] * length,
            p_rep=r['p_rep'] * rate,
            v_rep=r['v_rep'] * speed,
            r0_frict=(r['r0_rep'] + r['r0_frict_offset']) * length,
            c_frict=r['c_frict'],
            v_frict=r['v_frict'] * speed,
            p_frict=r['p_frict'] * rate,
            a_frict=r['a_frict'] * accel,
            r0_shill=r['r0_shill'] * length,
            v_shill=r['v_shill'] * speed,
            p_shill=r['p_shill'] * rate,
            a_shill=r['a_shill'] * accel,
        )


def braking_curve(r: FloatArray, a: float, p: float) -> FloatArray:
    """D(r, a, p): the largest velocity difference at distance r that still allows stopping (robotsim)."""
    r = np.asarray(r, dtype=float)
    linear = r * p
    root = np.sqrt(np.maximum(2.0 * a * r - a**2 / p**2, 0.0))
    return np.where(r <= 0.0, 0.0, np.where(linear < a / p, linear, root))


def flocking_command(
    positions: FloatArray, velocities: FloatArray, projection: Projection, params: FlockingParams
) -> FloatArray:
    """Desired velocities (2, N) of optimized flocking in a tube, capped at v_max and floored at v_min."""
    n = positions.shape[1]
    command = params.v_flock * projection.tangent
    diff = positions[:, :, None] - positions[:, None, :]  # r_i - r_j
    dist = np.hypot(diff[0], diff[1]) + np.eye(n) * 1e9
    unit = diff / dist
    repel = np.where(dist < params.r0_rep, np.minimum(params.p_rep * (params.r0_rep - dist), params.v_rep), 0.0)
    command = command + np.sum(repel * unit, axis=2)
    dv = velocities[:, None, :] - velocities[:, :, None]  # v_j - v_i
    v_ij = np.hypot(dv[0], dv[1])
    allowed = np.maximum(params.v_frict, braking_curve(dist - params.r0_frict, params.a_frict, params.p_frict))
    excess = np.where((v_ij > allowed) & (dist < 1e8), params.c_frict * (v_ij - allowed), 0.0)
    command = command + np.sum(excess * dv / np.maximum(v_ij, 1e-12), axis=2)
    for side in (1.0, -1.0):  # left wall (+n) and right wall (-n); each shill moves inward
        wall_distance = projection.half_width_m - side * projection.y_m
        shill_velocity = -side * params.v_shill * projection.normal
        dv_s = shill_velocity - velocities
        v_is = np.hypot(dv_s[0], dv_s[1])
        allowed_s = braking_curve(wall_distance - params.r0_shill, params.a_shill, params.p_shill)
        pull = np.where(v_is > allowed_s, v_is - allowed_s, 0.0)
        command = command + pull * dv_s / np.maximum(v_is, 1e-12)
    speed = np.hypot(command[0], command[1])
    target = np.clip(speed, params.v_min, params.v_max)
    scale = np.where(speed > 1e-12, target / np.maximum(speed, 1e-12), 0.0)
    return np.where(speed > 1e-12, command * scale, params.v_min * projection.tangent)
