"""The paper's second baseline: distributed nonlinear MPC for a swarm in a tube (Soria, Schiano, Floreano 2021;
``docs/theory.md`` §6.2).

Every agent is a double integrator p' = v, v' = u with |u_x|, |u_y| <= a_max, and solves its own problem over a
horizon of H steps of dt, minimising (weights from the first author's acados code, squared)

    sum_k  W_sep^2 / (M)^2 sum_j (|p_j(k) - p_i(k)|^2 - d_ref^2)^2      separation, M nearest neighbours
         + W_dir^2 (1 - (v(k) . t)^2 / |v(k)|^2)^2                      direction along the tube tangent t
         + W_nav^2 (|v(k)|^2 - v_ref^2)^2                                speed
         + W_u^2 |u(k)|^2                                                effort

subject to hard separation from the neighbours' last predicted trajectories, |p_i(k) - p_j(k)| >= d_safe, and the
tube walls linearised about the agent's previous prediction, |(p(k) - gamma(l_k)) . n(l_k)| <= lambda(l_k) - r_s,
both softened by slacks with an exact L1 penalty ``w_slack`` (a swarm can start inside a constraint: hard, the
problem would have no solution at all; soft, the slacks are zero whenever it has one). Each agent's problem is a small NLP, built once with CasADi (exact derivatives) and solved to convergence by IPOPT,
warm-started from its previous solution and multipliers, every ``update_s`` seconds; the agent keeps its first
acceleration in between ([`NmpcSwarm`][vtube_planning.baselines.nmpc.NmpcSwarm]). A solve that does not converge is
never applied: the agent follows the rest of its last converged plan instead, and the swarm counts it (``converged``,
``fallbacks``). As the paper ran it: v_ref = v_max, d_ref = 2 r_a, d_safe = 2 r_s, v_min = 0. CasADi is an optional
dependency (``pip install 'vtube[nmpc]'``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import ParamsError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.onboard import Projection
from vtube_planning.params import SwarmParams

FloatArray = NDArray[np.float64]

SLACK_TOLERANCE = 1e-4
"""A converged solve with a larger slack broke a constraint (m^2 for separation, m for the walls)."""


@dataclass(frozen=True)
class NmpcParams:
    """Horizon, weights and limits (SI units); [`for_swarm`][vtube_planning.baselines.nmpc.NmpcParams.for_swarm] sets
    them as the paper's comparison did."""

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
    max_iter: int = 200
    w_slack: float = 1e3

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


class AgentProblem:
    """One agent's NLP for a given number of neighbours, built once with CasADi and solved by IPOPT.

    Unknowns: the H accelerations (row by row, x = u.ravel()). Parameters: p0, v0, the tube tangent, the
    neighbours' predicted positions (M, H, 2), and the wall linearisation (feet and normals (H, 2), room (H,)).
    """

    def __init__(self, params: NmpcParams, neighbours: int) -> None:
        try:
            import casadi as ca
        except ImportError as err:  # an optional dependency
            msg = "the NMPC baseline needs CasADi; install it with: pip install 'vtube[nmpc]'"
            raise ParamsError(msg) from err
        h, m, dt = params.horizon, neighbours, params.dt_s
        self.h, self.m = h, m
        a_p, a_v = rollout_maps(h, dt)
        x = ca.SX.sym('u', 2 * h)
        par = ca.SX.sym('par', 6 + 2 * m * h + 5 * h)
        p0, v0, tangent = par[0:2], par[2:4], par[4:6]
        others = ca.reshape(par[6 : 6 + 2 * m * h], 2, m * h).T  # rows (j, k), columns x, y
        rest = par[6 + 2 * m * h :]
        foot, normal, room = ca.reshape(rest[: 2 * h], 2, h).T, ca.reshape(rest[2 * h : 4 * h], 2, h).T, rest[4 * h :]
        u = ca.reshape(x, 2, h).T  # (H, 2)
        steps = ca.DM(np.arange(1, h + 1) * dt)
        p = ca.repmat(p0.T, h, 1) + steps @ v0.T + ca.DM(a_p) @ u
        v = ca.repmat(v0.T, h, 1) + ca.DM(a_v) @ u
        speed2 = ca.fmax(ca.sum2(v**2), 1e-9)
        along = v @ tangent
        cost = params.w_dir**2 * ca.sumsqr(1.0 - along**2 / speed2)
        cost += params.w_nav**2 * ca.sumsqr(speed2 - params.v_ref**2)
        cost += params.w_u**2 * ca.sumsqr(u)
        offset = ca.sum2((p - foot) * normal)
        constraints = [room - offset, room + offset]
        if m:
            mine = ca.repmat(p, m, 1)  # row (j, k) holds p_k
            d2 = ca.sum2((others - mine) ** 2)
            cost += params.w_sep**2 / m**2 * ca.sumsqr(d2 - params.d_ref**2)
            constraints.append(d2 - params.d_safe**2)
        g = ca.vertcat(*constraints)
        self.n_g = g.shape[0]
        slack = ca.SX.sym('s', self.n_g)  # soft constraints (exact L1 penalty): every problem has a solution
        options: dict[str, Any] = {
            'print_time': False,
            'ipopt.print_level': 0,
            'ipopt.sb': 'yes',
            'ipopt.max_iter': params.max_iter,
            'ipopt.tol': 1e-6,
            'ipopt.warm_start_init_point': 'yes',
        }
        self.terms = ca.Function('terms', [x, par], [cost, g])  # for checks: f and g without the slacks
        problem = {'x': ca.vertcat(x, slack), 'p': par, 'f': cost + params.w_slack * ca.sum1(slack), 'g': g + slack}
        self.solver: Any = ca.nlpsol('nmpc', 'ipopt', problem, options)
        self.lbx = np.concatenate([np.full(2 * h, -params.a_max), np.zeros(self.n_g)])
        self.ubx = np.concatenate([np.full(2 * h, params.a_max), np.full(self.n_g, np.inf)])

    def pack(
        self, p0: FloatArray, v0: FloatArray, tangent: FloatArray, others: FloatArray, walls: Projection, margin: float
    ) -> FloatArray:
        """The parameter vector: the agent's state, the neighbours' predictions and the walls about ``walls``."""
        room = walls.half_width_m - margin
        return np.concatenate(
            [p0, v0, tangent, others.reshape(-1), walls.foot_m.T.reshape(-1), walls.normal.T.reshape(-1), room]
        )

    def solve(
        self, guess: FloatArray, multipliers: tuple[FloatArray, FloatArray] | None, values: FloatArray
    ) -> tuple[FloatArray, tuple[FloatArray, FloatArray], bool, float]:
        """IPOPT from ``guess`` (and the last multipliers): accelerations (H, 2), multipliers, converged, and the
        largest slack (how far the solution breaks a constraint; 0 when they all hold)."""
        start: dict[str, Any] = {'x0': np.concatenate([guess.ravel(), np.zeros(self.n_g)]), 'p': values}
        start |= {'lbx': self.lbx, 'ubx': self.ubx, 'lbg': 0.0, 'ubg': np.inf}
        if multipliers is not None:
            start |= {'lam_x0': multipliers[0], 'lam_g0': multipliers[1]}
        solution = self.solver(**start)
        converged = bool(self.solver.stats()['success'])
        lam = (np.asarray(solution['lam_x']).ravel(), np.asarray(solution['lam_g']).ravel())
        x = np.asarray(solution['x']).ravel()
        return x[: 2 * self.h].reshape(self.h, 2), lam, converged, float(x[2 * self.h :].max(initial=0.0))


@dataclass
class NmpcSwarm:
    """Every agent's MPC, solved in turn each update against the others' last predictions (distributed).

    ``solves``, ``converged`` and ``fallbacks`` count the agents' solves, those IPOPT solved to its tolerance, and
    those not converged, after which the agent kept following its last converged plan; ``softened`` the converged
    ones that had to break a separation or wall constraint (a slack above ``SLACK_TOLERANCE``).
    """

    tube: VirtualTube
    params: NmpcParams
    plans: FloatArray = field(default_factory=lambda: np.zeros((0, 0, 2)))  # (N, H, 2) accelerations, warm starts
    predictions: FloatArray = field(default_factory=lambda: np.zeros((0, 0, 2)))  # (N, H, 2) predicted positions
    held: FloatArray = field(default_factory=lambda: np.zeros((2, 0)))  # (2, N) accelerations held between updates
    next_update_s: float = 0.0
    time_s: float = 0.0
    solves: int = 0
    converged: int = 0
    fallbacks: int = 0
    softened: int = 0
    solve_time_s: float = 0.0
    problems: dict[int, AgentProblem] = field(default_factory=dict)
    multipliers: dict[int, tuple[FloatArray, FloatArray]] = field(default_factory=dict)

    @property
    def converged_share(self) -> float:
        """The share of solves that converged (NaN before the first)."""
        return self.converged / self.solves if self.solves else float('nan')

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
        capped: FloatArray = command * np.minimum(1.0, self.params.v_max / np.maximum(speed, 1e-12))
        return capped

    def _update(self, positions: FloatArray, velocities: FloatArray, projection: Projection) -> None:
        started = time.perf_counter()
        params, n = self.params, positions.shape[1]
        others_all = self.predictions.copy()
        for i in range(n):
            dist = np.hypot(*(positions - positions[:, [i]]))
            dist[i] = np.inf
            near = np.argsort(dist)[: min(params.neighbours, n - 1)]
            u = self._solve(i, positions[:, i], velocities[:, i], projection.tangent[:, i], others_all[near])
            self.plans[i] = np.vstack([u[1:], u[-1:]])  # shifted: the next warm start, or the fallback
            self.predictions[i] = rollout(positions[:, i], velocities[:, i], u, params.dt_s)[0]
            self.held[:, i] = u[0]
        self.solve_time_s += time.perf_counter() - started

    def _solve(self, i: int, p0: FloatArray, v0: FloatArray, tangent: FloatArray, others: FloatArray) -> FloatArray:
        """Agent i's accelerations (H, 2): IPOPT's when it converged, else the rest of its last converged plan."""
        params = self.params
        m = others.shape[0]
        if m not in self.problems:
            self.problems[m] = AgentProblem(params, m)
        walls = self.tube.project(self.predictions[i].T)  # linearise the walls about the previous prediction
        values = self.problems[m].pack(p0, v0, tangent, others, walls, params.wall_margin)
        u, lam, converged, slack = self.problems[m].solve(self.plans[i], self.multipliers.get(i), values)
        self.solves += 1
        if converged:
            self.converged += 1
            self.softened += slack > SLACK_TOLERANCE
            self.multipliers[i] = lam
            return np.clip(u, -params.a_max, params.a_max)
        self.fallbacks += 1
        self.multipliers.pop(i, None)
        plan: FloatArray = self.plans[i]
        return plan
