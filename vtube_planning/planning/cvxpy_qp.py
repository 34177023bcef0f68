"""The reference formulation of the planner's convex subproblem, in cvxpy (Clarabel).

The slowness-form QP of one convex-concave iteration (``docs/theory.md`` §8.1), built once with cvxpy parameters and
re-solved (DPP) with new tangents:

* (p2), (p5): bounds at the grid points (linear interpolation stays between them);
* (p4): w_k >= 1 / min sqrt(a_n r_t) over the two intervals around l_k;
* (p6): |rho_{k+1} - rho_k| <= a_rho dl min(w_k, w_{k+1})  (the interval's largest speed);
* (p7), local width: c_k rho_i <= a_rho dl_p w_j for i, j in {k, k+1}, with c_k the largest
  |lambda(l) / lambda(l + dl_p) - 1| on the interval; rigid shift: the convex form of ``docs/theory.md`` §8.3 at the
  grid points, with the footprint frozen at the previous iterate, a cone; ``'none'`` leaves (p7) out;
* (p3): |w_{k+1} - w_k| <= a_v dl min(w_k, w_{k+1})^3, with w^3 replaced by its tangent at the previous iterate.

The objective is exact for the interpolated plan: integral of w plus mu times the integral of (rho - rho_d)^2.
`banded_qp` solves the same QP for the linear readings of (p7); this one is the readable reference and solves
the rigid shift.
"""

from __future__ import annotations

import math

import cvxpy as cp
import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import SolverError
from vtube_planning.onboard import swarm_area
from vtube_planning.planning.braking import braking_tangent
from vtube_planning.planning.constraints import RHO_EPSILON
from vtube_planning.planning.density import footprint
from vtube_planning.planning.last_out import QuadraticModel
from vtube_planning.planning.problem import Problem

FloatArray = NDArray[np.float64]

SOLVER_OPTIONS: dict[str, float] = {}
"""Clarabel options (its defaults suffice: the constraints are normalised to order one)."""


class ConvexPlanner:
    """The slowness-form QP of one convex-concave iteration, built once and re-solved with new tangents."""

    def __init__(self, problem: Problem) -> None:
        self.problem = problem
        swarm, options = problem.swarm, problem.options
        n = problem.l_m.size
        dl = problem.dl_m
        self.w = cp.Variable(n, name='w')
        self.rho = cp.Variable(n, name='rho')
        # tangent of w^3 at the previous iterate, normalised: dw / (a_v dl wbar^3) <= 3 w / wbar - 2, at both ends
        self.inv_scale = {end: cp.Parameter(n - 1, nonneg=True, name=f'inv_scale_{end}') for end in ('left', 'right')}
        self.slope = cp.Parameter(n, nonneg=True, name='slope')
        w, rho = self.w, self.rho
        dw = w[1:] - w[:-1]
        cons = [
            w >= 1.0 / problem.speed_cap_mps,
            w <= 1.0 / swarm.v_min_mps,
            rho >= RHO_EPSILON,
            rho <= swarm.rho_max_per_m2,
            w[0] == 1.0 / problem.v0_mps,
            rho[0] == problem.rho0_per_m2,
        ]
        for end, j in (('left', slice(None, -1)), ('right', slice(1, None))):  # both ends of every interval
            tangent = cp.multiply(self.slope[j], w[j]) - 2.0
            inv_scale = self.inv_scale[end]
            cons += [cp.multiply(inv_scale, dw) <= tangent, -cp.multiply(inv_scale, dw) <= tangent]
            cons += [cp.abs(rho[1:] - rho[:-1]) <= cp.multiply(swarm.a_rho * dl, w[j])]  # (p6)
        cons += self._braking_rows(n)
        self.footprint_gap: cp.Parameter | None = None
        self.footprint_root: cp.Parameter | None = None
        if options.predictive_model == 'local_width':
            ratio = problem.width_ratio
            budget = swarm.a_rho * options.lookahead_m
            for i in (slice(None, -1), slice(1, None)):
                for j in (slice(None, -1), slice(1, None)):
                    cons.append(cp.multiply(ratio, rho[i]) <= budget * w[j])
        elif options.predictive_model == 'rigid_shift':
            # rho^2 |D| / (N + D rho) <= a_rho dl_p w, with the footprint change D frozen (docs/theory.md §8.3)
            self.footprint_gap = cp.Parameter(n, name='footprint_gap')
            self.footprint_root = cp.Parameter(n, nonneg=True, name='footprint_root')
            x = cp.multiply(self.footprint_root, rho)
            y = swarm.n_robots + cp.multiply(self.footprint_gap, rho)
            t = swarm.a_rho * options.lookahead_m * w
            cons.append(cp.SOC(y + t, cp.vstack([2.0 * x, y - t]), axis=0))
        e = rho - swarm.rho_d_per_m2
        node_dl = 0.5 * (np.concatenate([dl, [0.0]]) + np.concatenate([[0.0], dl]))
        time_term = node_dl @ w
        root = np.sqrt(dl)
        density_term = options.density_weight * (
            0.25 * cp.sum_squares(cp.multiply(root, e[:-1] + e[1:]))
            + cp.sum_squares(cp.multiply(root, e[1:] - e[:-1])) / 12.0
        )
        objective = time_term + density_term
        # the last-robot-out exit term's convex model (last_out.ExitTerm.model), re-set at every iterate
        self.end_linear = cp.Parameter(2, name='end_linear')
        self.end_curvature = cp.Parameter(2, nonneg=True, name='end_curvature')
        self.end_constant = cp.Parameter(name='end_constant')
        if options.objective == 'last_out':
            ends = cp.hstack([w[-1], rho[-1]])
            objective += self.end_linear @ ends + 0.5 * self.end_curvature @ cp.square(ends) + self.end_constant
        self.cvx = cp.Problem(cp.Minimize(objective), cons)
        self.value = math.nan

    def _braking_rows(self, n: int) -> list[cp.Constraint]:
        """The room for braking (none unless ``braking_room``): min(w) >= h(max(rho)) per interval, with h's tangent
        at the previous iterate as parameters (`braking.braking_tangent`)."""
        self.braking = (cp.Parameter(n, nonneg=True, name='braking_slope'), cp.Parameter(n, name='braking_intercept'))
        if not self.problem.options.braking_room:
            return []
        ends = (slice(None, -1), slice(1, None))
        slope, intercept = self.braking
        return [self.w[i] >= cp.multiply(slope[j], self.rho[j]) + intercept[j] for i in ends for j in ends]

    def set_tangent(self, w_bar: FloatArray, rho_bar: FloatArray) -> None:
        """Linearise (p3) at ``w_bar``; for the rigid shift, freeze the footprint at ``rho_bar``."""
        swarm, options = self.problem.swarm, self.problem.options
        dl = self.problem.dl_m
        self.inv_scale['left'].value = 1.0 / (swarm.a_v_mps2 * dl * w_bar[:-1] ** 3)
        self.inv_scale['right'].value = 1.0 / (swarm.a_v_mps2 * dl * w_bar[1:] ** 3)
        self.slope.value = 3.0 / w_bar
        if options.braking_room:
            self.braking[0].value, self.braking[1].value = braking_tangent(swarm, rho_bar)
        if self.footprint_gap is not None and self.footprint_root is not None:
            back, front = footprint(self.problem.tube, self.problem.l_m, rho_bar, swarm.n_robots)
            shifted = swarm_area(self.problem.tube, back + options.lookahead_m, front + options.lookahead_m, 0.0)
            gap = shifted - swarm_area(self.problem.tube, back, front, 0.0)
            self.footprint_gap.value = gap
            self.footprint_root.value = np.sqrt(np.abs(gap))

    def set_exit_model(self, model: QuadraticModel) -> None:
        """Set the convex model of the last-robot-out exit term (planned with ``objective = 'last_out'`` only)."""
        self.end_linear.value = np.array(model.linear)
        self.end_curvature.value = np.array(model.curvature)
        self.end_constant.value = model.constant

    def solve(self) -> tuple[FloatArray, FloatArray]:
        """Solve the current subproblem: the slowness and the density; (p1) is left in `value`."""
        try:
            self.cvx.solve(solver=cp.CLARABEL, **SOLVER_OPTIONS)
        except cp.error.SolverError as err:
            msg = f'Clarabel failed on a planning subproblem shown feasible beforehand: {err}'
            raise SolverError(msg) from err
        if self.cvx.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE):
            msg = f'Clarabel returned status {self.cvx.status!r} on a planning subproblem shown feasible beforehand.'
            raise SolverError(msg)
        self.value = float(self.cvx.value)
        return np.asarray(self.w.value, dtype=float), np.asarray(self.rho.value, dtype=float)
