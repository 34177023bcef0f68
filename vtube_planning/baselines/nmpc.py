"""The paper's second baseline: distributed nonlinear MPC for a swarm in a tube (Soria, Schiano, Floreano 2021;
``docs/theory.md`` §6.2).

Every agent is a double integrator p' = v, v' = u with |u_x|, |u_y| <= a_max, and solves its own problem over a
horizon of H steps of dt, minimising (weights from the first author's acados code, squared)

    sum_k  W_sep^2 / (M)^2 sum_j (|p_j(k) - p_i(k)|^2 - d_ref^2)^2      separation, M nearest neighbours
         + W_dir^2 (1 - (v(k) . t)^2 / |v(k)|^2)^2                      direction along the tube tangent t
         + W_nav^2 (|v(k)|^2 - v_ref^2)^2                                speed
         + W_u^2 |u(k)|^2                                                effort

subject to hard separation from the neighbours' last predicted trajectories, |p_i(k) - p_j(k)| >= d_safe, and the
tube walls linearised about the agent's previous prediction, |(p(k) - gamma(l_k)) . n(l_k)| <= lambda(l_k) - r_s.
Each agent solves with scipy SLSQP, warm-started from its previous solution, every ``update_s`` seconds and keeps
its first acceleration in between (:class:`NmpcSwarm`). As the paper ran it: v_ref = v_max, d_ref = 2 r_a,
d_safe = 2 r_s, v_min = 0.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import minimize

from vtube_planning.errors import ParamsError
from vtube_planning.geometry.tube import Projection, VirtualTube
from vtube_planning.params import SwarmParams

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class NmpcParams:
    """Horizon, weights and limits (SI units); :meth:`for_swarm` sets them as the paper's comparison did."""

    horizon: int = 10
    dt_s: float = 0.15
    update_s: float = 0.1
    a_max: float = 2.0
    v_max: float = 5.0
    v_ref: float = 5.0
    d_ref: float = 1.6
    d_safe: float = 0.8
    wall_margin: float = 0.4
    neighbours: int = 3
    w_sep: float = 1.0
    w_dir: float = 1.0
    w_nav: float = 2.0
    w_u: float = 0.1
    max_iter: int = 30

    def __post_init__(self) -> None:
        if self.horizon < 1 or self.neighbours < 0 or self.max_iter < 1:
            msg = f'NMPC horizon, neighbours and max_iter must be positive integers; got {self}.'
            raise ParamsError(msg)
        if not (self.dt_s > 0 and self.update_s > 0 and self.a_max > 0 and self.v_max > 0):
            msg = f'NMPC dt_s, update_s, a_max and v_max must be > 0; got {self}.'
            raise ParamsError(msg)

    @classmethod
    def for_swarm(cls, swarm: SwarmParams) -> NmpcParams:
        """v_ref = v_max, d_ref = 2 r_a, d_safe = 2 r_s, wall margin r_s (``docs/theory.md`` §6.2, Table 1 radii)."""
        return cls(
            v_max=swarm.v_max_mps,
            v_ref=swarm.v_max_mps,
            d_ref=2 * swarm.r_a_m,
            d_safe=2 * swarm.r_s_m,
            wall_margin=swarm.r_s_m,
        )


def rollout(p0: FloatArray, v0: FloatArray, u: FloatArray, dt: float) -> tuple[FloatArray, FloatArray]:
    """Positions and velocities (H, 2) after each of the H accelerations u (H, 2), exact for piecewise-constant u."""
    v = v0 + dt * np.cumsum(u, axis=0)
    v_prev = np.vstack([v0, v[:-1]])
    p = p0 + np.cumsum(dt * v_prev + 0.5 * dt**2 * u, axis=0)
    return p, v


def rollout_maps(horizon: int, dt: float) -> tuple[FloatArray, FloatArray]:
    """The rollout is affine in u: p = p0 + (k+1) dt v0 + A_p u, v = v0 + A_v u per axis; returns (A_p, A_v), (H, H)."""
    basis = np.eye(horizon)
    a_p = np.empty((horizon, horizon))
    a_v = np.empty((horizon, horizon))
    for m in range(horizon):
        u = np.zeros((horizon, 2))
        u[:, 0] = basis[m]
        p, v = rollout(np.zeros(2), np.zeros(2), u, dt)
        a_p[:, m], a_v[:, m] = p[:, 0], v[:, 0]
    return a_p, a_v


def cost_gradients(
    p: FloatArray, v: FloatArray, u: FloatArray, others: FloatArray, tangent: FloatArray, params: NmpcParams
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """d(total cost)/dp, /dv and the direct /du, each (H, 2)."""
    d_p = np.zeros_like(p)
    if others.shape[0]:
        rel = others - p[None]
        d2 = np.sum(rel**2, axis=2)
        d_p = -4.0 * params.w_sep**2 / others.shape[0] ** 2 * np.sum((d2 - params.d_ref**2)[:, :, None] * rel, axis=0)
    speed2 = np.maximum(np.sum(v**2, axis=1), 1e-9)
    along = v @ tangent
    share = along**2 / speed2
    d_share = 2 * along[:, None] * tangent[None] / speed2[:, None] - 2 * (along**2)[:, None] * v / speed2[:, None] ** 2
    d_v = params.w_dir**2 * 2 * (1 - share)[:, None] * (-d_share)
    d_v += params.w_nav**2 * 4 * (speed2 - params.v_ref**2)[:, None] * v
    return d_p, d_v, 2 * params.w_u**2 * u


def stage_costs(
    p: FloatArray, v: FloatArray, u: FloatArray, others: FloatArray, tangent: FloatArray, params: NmpcParams
) -> dict[str, float]:
    """The four cost terms over the horizon; ``others`` (M, H, 2) are the neighbours' predicted positions."""
    if others.shape[0]:
        d2 = np.sum((others - p[None]) ** 2, axis=2)
        sep = params.w_sep**2 / others.shape[0] ** 2 * float(np.sum((d2 - params.d_ref**2) ** 2))
    else:
        sep = 0.0
    speed2 = np.maximum(np.sum(v**2, axis=1), 1e-9)
    direction = params.w_dir**2 * float(np.sum((1.0 - (v @ tangent) ** 2 / speed2) ** 2))
    navigation = params.w_nav**2 * float(np.sum((speed2 - params.v_ref**2) ** 2))
    effort = params.w_u**2 * float(np.sum(u**2))
    return {'separation': sep, 'direction': direction, 'navigation': navigation, 'effort': effort}


def wall_slack(p: FloatArray, foot: FloatArray, normal: FloatArray, room: FloatArray) -> FloatArray:
    """The linearised wall constraints (>= 0 inside): room -/+ (p - foot) . n for each of the H positions, (2H,)."""
    offset = np.sum((p - foot) * normal, axis=1)
    return np.concatenate([room - offset, room + offset])


@dataclass
class NmpcSwarm:
    """Every agent's MPC, solved in turn each update against the others' last predictions (distributed)."""

    tube: VirtualTube
    params: NmpcParams
    plans: FloatArray = field(default_factory=lambda: np.zeros((0, 0, 2)))  # (N, H, 2) accelerations, warm starts
    predictions: FloatArray = field(default_factory=lambda: np.zeros((0, 0, 2)))  # (N, H, 2) predicted positions
    held: FloatArray = field(default_factory=lambda: np.zeros((2, 0)))  # (2, N) accelerations held between updates
    next_update_s: float = 0.0
    time_s: float = 0.0
    failures: int = 0
    solves: int = 0
    solve_time_s: float = 0.0

    def command(self, positions: FloatArray, velocities: FloatArray, projection: Projection, dt_s: float) -> FloatArray:
        """Velocity commands (2, N): the current velocities advanced by the held accelerations, capped at v_max."""
        n, h = positions.shape[1], self.params.horizon
        if self.plans.shape[0] != n:  # the first call: no plans yet
            self.plans = np.zeros((n, h, 2))
            steps = np.arange(1, h + 1)[:, None, None] * self.params.dt_s
            self.predictions = (positions.T[None] + steps * velocities.T[None]).transpose(1, 0, 2)
            self.held = np.zeros((2, n))
        if self.time_s >= self.next_update_s - 1e-12:
            self._update(positions, velocities, projection)
            self.next_update_s += self.params.update_s
        self.time_s += dt_s
        command = velocities + dt_s * self.held
        speed = np.hypot(command[0], command[1])
        return command * np.minimum(1.0, self.params.v_max / np.maximum(speed, 1e-12))

    def _update(self, positions: FloatArray, velocities: FloatArray, projection: Projection) -> None:
        started = time.perf_counter()
        params, n = self.params, positions.shape[1]
        plans, predictions, held = self.plans, self.predictions, self.held
        others_all = predictions.copy()
        for i in range(n):
            dist = np.hypot(*(positions - positions[:, [i]]))
            dist[i] = np.inf
            near = np.argsort(dist)[: min(params.neighbours, n - 1)]
            others = others_all[near]
            u, pred = self._solve(
                positions[:, i], velocities[:, i], projection.tangent[:, i], others, plans[i], predictions[i]
            )
            plans[i] = np.vstack([u[1:], u[-1:]])  # shifted warm start
            predictions[i] = pred
            held[:, i] = u[0]
        self.solve_time_s += time.perf_counter() - started

    def _solve(
        self,
        p0: FloatArray,
        v0: FloatArray,
        tangent: FloatArray,
        others: FloatArray,
        guess: FloatArray,
        previous: FloatArray,
    ) -> tuple[FloatArray, FloatArray]:
        params = self.params
        h, dt = params.horizon, params.dt_s
        a_p, a_v = rollout_maps(h, dt)
        walls = self.tube.project(previous.T)  # linearise the walls about the previous prediction
        foot, normal = walls.foot_m.T, walls.normal.T
        room = walls.half_width_m - params.wall_margin
        wall_jac = np.stack([normal[:, 0:1] * a_p, normal[:, 1:2] * a_p], axis=2).reshape(h, 2 * h)

        def unpack(x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
            u = x.reshape(h, 2)
            p, v = rollout(p0, v0, u, dt)
            return u, p, v

        def cost(x: FloatArray) -> float:
            u, p, v = unpack(x)
            return sum(stage_costs(p, v, u, others, tangent, params).values())

        def cost_grad(x: FloatArray) -> FloatArray:
            u, p, v = unpack(x)
            d_p, d_v, d_u = cost_gradients(p, v, u, others, tangent, params)
            return (a_p.T @ d_p + a_v.T @ d_v + d_u).ravel()

        def separation(x: FloatArray) -> FloatArray:
            _, p, _ = unpack(x)
            return (np.sum((others - p[None]) ** 2, axis=2) - params.d_safe**2).ravel()

        def separation_jac(x: FloatArray) -> FloatArray:
            _, p, _ = unpack(x)
            rel = -2.0 * (others - p[None])  # d/dp_k of |o_k - p_k|^2, (M, H, 2)
            jac = rel[:, :, None, :] * a_p[None, :, :, None]  # (M, H, H, 2): row (j, k), column (m, axis)
            return jac.reshape(others.shape[0] * h, 2 * h)

        def wall(x: FloatArray) -> FloatArray:
            return wall_slack(unpack(x)[1], foot, normal, room)

        constraints = [{'type': 'ineq', 'fun': wall, 'jac': lambda x: np.vstack([-wall_jac, wall_jac])}]
        if others.shape[0]:
            constraints.append({'type': 'ineq', 'fun': separation, 'jac': separation_jac})
        result = minimize(
            cost,
            guess.ravel(),
            jac=cost_grad,
            method='SLSQP',
            bounds=[(-params.a_max, params.a_max)] * (2 * h),
            constraints=constraints,
            options={'maxiter': params.max_iter, 'ftol': 1e-6},
        )
        self.solves += 1
        if not result.success:
            self.failures += 1  # keep the best iterate: the agent must still act
        u, p, _ = unpack(np.clip(result.x, -params.a_max, params.a_max))
        return u, p
