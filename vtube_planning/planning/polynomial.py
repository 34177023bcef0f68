"""The paper's segmented planning: cubic polynomials per segment, posed convexly (``docs/theory.md`` §8.5).

On each segment [L_{j-1}, L_j] the slowness w and the density rho are cubic Bernstein polynomials (the paper
parameterises v; parameterising w keeps the problem convex). Segments end at the breakpoints of the tube's
width and curvature and are at most L/12 long; both polynomials are C^1 across segment ends. Constraints:

* (p2), (p4), (p5): on the control points (convex-hull property: they then hold everywhere, conservatively);
* (p3), (p6), (p7, local width): at 9 collocation points per segment (between them they are not enforced);
* (p3) |w'| <= a_v w^3 by the convex-concave procedure, with an l1-penalised slack because a cubic cannot
  always follow the feasible start exactly; the slack vanishes in a few iterations.

The segments are solved jointly. The objective (integral of w plus mu times the integral of (rho - rho_d)^2) is
exact for the polynomials (Bernstein Gram matrices). The returned [`Plan`][vtube_planning.planning.plan.Plan] samples
the polynomials at a quarter of the planning grid step; its certificate is evaluated like every plan's.
"""

from __future__ import annotations

import itertools
import math
import time
from math import comb

import cvxpy as cp
import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import PlanError, SolverError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.params import PlanningOptions, SwarmParams
from vtube_planning.planning.constraints import RHO_EPSILON, curvature_speed_limit
from vtube_planning.planning.plan import Plan, PolynomialFit, SolveRecord, Status, make_plan
from vtube_planning.planning.problem import SUBSAMPLES, Problem, discretise

FloatArray = NDArray[np.float64]

COLLOCATION = np.linspace(0.0, 1.0, 9)
"""Collocation points per segment, in the segment's own parameter s in [0, 1]."""
SEGMENTS_PER_TUBE = 12
"""Segments are at most L / SEGMENTS_PER_TUBE long."""
SLACK_PENALTY = 1e3
"""Weight of the l1 slack of (p3) in the objective (s per unit of normalised violation)."""


def bernstein(s: FloatArray, degree: int = 3) -> FloatArray:
    """Bernstein basis of the given degree at s, shape (len(s), degree + 1)."""
    s = np.asarray(s, dtype=float)[:, None]
    i = np.arange(degree + 1)[None, :]
    return np.array([comb(degree, k) for k in range(degree + 1)]) * s**i * (1.0 - s) ** (degree - i)


def segment_knots(tube: VirtualTube) -> FloatArray:
    """Segment ends: 0, L, the width and curvature breakpoints, each segment split to at most L / 12."""
    length = tube.length_m
    raw = np.unique(np.concatenate([[0.0, length], tube.width.breakpoints, tube.center.breakpoints]))
    raw = raw[np.concatenate([[True], np.diff(raw) > 1e-6 * length])]
    knots = [0.0]
    for a, b in itertools.pairwise(raw):
        pieces = math.ceil((b - a) / (length / SEGMENTS_PER_TUBE) - 1e-9)
        knots.extend(np.linspace(a, b, pieces + 1)[1:])
    return np.array(knots)


def plan_polynomial(
    tube: VirtualTube,
    swarm: SwarmParams,
    options: PlanningOptions,
    *,
    scene: str = '',
    max_iterations: int = 60,
    rtol: float = 1e-9,
) -> Plan:
    """Plan speed and density with C^1 cubic segments (the paper's segmented planning), for comparison.

    Raises
    ------
    PlanError
        When the problem is infeasible (same checks as the convex method), or for the rigid-shift reading of
        (p7), the last-robot-out objective or the room for braking, which this method does not implement.
    """
    if options.predictive_model != 'local_width':
        msg = "the polynomial method implements the local-width reading of (p7) only; use method 'convex'."
        raise PlanError(msg)
    if options.objective != 'centre':
        msg = "the polynomial method plans for the centre's time only (objective 'centre'); use method 'convex'."
        raise PlanError(msg)
    if options.braking_room:
        msg = "the polynomial method does not keep the room for braking (braking_room); use method 'convex'."
        raise PlanError(msg)
    started = time.perf_counter()
    problem = discretise(tube, swarm, options)
    qp = _SegmentQP(problem, segment_knots(tube))
    status, iterations = qp.iterate(np.interp(qp.l_colloc, problem.l_m, problem.w_start), max_iterations, rtol)
    samples = np.linspace(0.0, tube.length_m, 4 * (problem.l_m.size - 1) + 1)
    w, rho = qp.sampled(samples)
    solved = SolveRecord(
        'polynomial',
        status,
        iterations,
        time.perf_counter() - started,
        polynomial=PolynomialFit(qp.h.size, float(qp.objective.value), _total(qp.slack.value)),
    )
    return make_plan(tube, swarm, options, samples, 1.0 / w, rho, solved=solved, scene=scene)


class _SegmentQP:
    """The segments' QP of one convex-concave iteration, built once with cvxpy parameters: control points of w and
    rho per segment, (p3) linearised at the collocation points with an l1-penalised slack."""

    def __init__(self, problem: Problem, knots: FloatArray) -> None:
        tube, swarm, options = problem.tube, problem.swarm, problem.options
        self.a_v_mps2 = swarm.a_v_mps2
        self.knots = knots
        h = self.h = np.diff(knots)
        m = h.size
        basis = bernstein(COLLOCATION)
        d_basis = 3.0 * (bernstein(COLLOCATION, 2) @ (np.eye(4, k=1)[:3] - np.eye(4)[:3]))  # d/ds in control points
        l_colloc = self.l_colloc = (knots[:-1, None] + h[:, None] * COLLOCATION[None, :]).ravel()
        sub = np.linspace(knots[:-1], knots[1:], SUBSAMPLES * 4 + 1, axis=1)
        limit = curvature_speed_limit(tube, swarm, sub.ravel()).reshape(sub.shape).min(axis=1)
        cap = np.minimum(limit, swarm.v_max_mps)
        ratio = np.abs(
            np.asarray(tube.half_width(l_colloc)) / np.asarray(tube.half_width(l_colloc + options.lookahead_m)) - 1.0
        )
        P = self.w_control = cp.Variable((m, 4), name='w_control')
        Q = self.rho_control = cp.Variable((m, 4), name='rho_control')
        slack = self.slack = cp.Variable(l_colloc.size, nonneg=True, name='p3_slack')
        inv_scale = self.inv_scale = cp.Parameter(l_colloc.size, nonneg=True)
        slope = self.slope = cp.Parameter(l_colloc.size, nonneg=True)
        w_at = self.w_at = cp.vec(basis @ P.T, order='F')  # segment-major, matching l_colloc
        dw_at = cp.vec(d_basis @ P.T @ np.diag(1.0 / h), order='F')
        rho_at = cp.vec(basis @ Q.T, order='F')
        drho_at = cp.vec(d_basis @ Q.T @ np.diag(1.0 / h), order='F')
        cons = [
            P >= (1.0 / cap)[:, None],
            P <= 1.0 / swarm.v_min_mps,
            Q >= RHO_EPSILON,
            Q <= swarm.rho_max_per_m2,
            P[0, 0] == 1.0 / problem.v0_mps,
            Q[0, 0] == problem.rho0_per_m2,
            cp.abs(cp.multiply(inv_scale, dw_at)) <= cp.multiply(slope, w_at) - 2.0 + slack,
            cp.abs(drho_at) <= swarm.a_rho * w_at,
            cp.multiply(ratio, rho_at) <= swarm.a_rho * options.lookahead_m * w_at,
        ]
        if m > 1:
            cons += [P[:-1, 3] == P[1:, 0], Q[:-1, 3] == Q[1:, 0]]
            cons += [cp.multiply(1.0 / h[:-1], P[:-1, 3] - P[:-1, 2]) == cp.multiply(1.0 / h[1:], P[1:, 1] - P[1:, 0])]
            cons += [cp.multiply(1.0 / h[:-1], Q[:-1, 3] - Q[:-1, 2]) == cp.multiply(1.0 / h[1:], Q[1:, 1] - Q[1:, 0])]
        gram = np.array([[comb(3, i) * comb(3, k) / (7.0 * comb(6, i + k)) for k in range(4)] for i in range(4)])
        root = np.linalg.cholesky(gram).T  # q' G q = |root q|^2
        e = Q - swarm.rho_d_per_m2  # Bernstein bases sum to one, so shifting every control point shifts rho
        time_term = cp.sum(cp.multiply(h / 4.0, cp.sum(P, axis=1)))
        density_term = options.density_weight * cp.sum(cp.multiply(h, cp.sum(cp.square(e @ root.T), axis=1)))
        self.objective = time_term + density_term
        self.cvx = cp.Problem(cp.Minimize(self.objective + SLACK_PENALTY * cp.sum(slack)), cons)

    def iterate(self, w_bar: FloatArray, max_iterations: int, rtol: float) -> tuple[Status, int]:
        """The convex-concave procedure from ``w_bar`` at the collocation points: its status and iterations."""
        previous = math.inf
        status: Status = 'iteration limit'
        iterations = 0
        for iterations in range(1, max_iterations + 1):  # the final count is reported below
            self.inv_scale.value = 1.0 / (self.a_v_mps2 * w_bar**3)
            self.slope.value = 3.0 / w_bar
            try:
                self.cvx.solve(solver=cp.CLARABEL)
            except cp.error.SolverError as err:
                msg = f'Clarabel failed on a polynomial planning subproblem: {err}'
                raise SolverError(msg) from err
            if self.cvx.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE):
                msg = f'Clarabel returned status {self.cvx.status!r} on a polynomial planning subproblem.'
                raise SolverError(msg)
            w_bar = np.asarray(self.w_at.value, dtype=float)
            value = float(self.cvx.value)
            if previous - value <= rtol * max(1.0, abs(value)) and _total(self.slack.value) <= 1e-9:
                status = 'converged'
                break
            previous = value
        return status, iterations

    def sampled(self, samples: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The solved polynomials' slowness and density at the arc lengths ``samples``."""
        knots, h = self.knots, self.h
        seg = np.clip(np.searchsorted(knots, samples, side='right') - 1, 0, h.size - 1)
        local = bernstein((samples - knots[seg]) / h[seg])
        # an optimal solve sets every value
        w = np.einsum('ij,ij->i', local, np.asarray(self.w_control.value, dtype=float)[seg])
        rho = np.einsum('ij,ij->i', local, np.asarray(self.rho_control.value, dtype=float)[seg])
        return w, rho


def _total(value: object) -> float:
    """The sum of a solved cvxpy variable's value."""
    return float(np.sum(np.asarray(value, dtype=float)))
