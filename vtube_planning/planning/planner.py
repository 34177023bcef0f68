"""Speed and density planning (paper (p1)-(p8)) in the convex slowness form of ``docs/theory.md`` §8.1.

Unknowns on an arc-length grid l_0..l_K: the slowness w = 1/v and the density rho, both interpolated linearly
between grid points (:class:`~vtube_planning.planning.plan.Plan`). Each constraint is imposed so that it holds on every
interval, not only at the grid points:

* (p2), (p5): bounds at the grid points (linear interpolation stays between them);
* (p4): w_k >= 1 / min sqrt(a_n r_t) over the two intervals around l_k;
* (p6): |rho_{k+1} - rho_k| <= a_rho dl min(w_k, w_{k+1})  (the interval's largest speed);
* (p7), local width: c_k rho_i <= a_rho dl_p w_j for i, j in {k, k+1}, with c_k the largest
  |lambda(l) / lambda(l + dl_p) - 1| on the interval; rigid shift: the convex form of ``docs/theory.md`` §8.3 at the
  grid points, with the footprint frozen at the previous iterate; ``'none'`` leaves (p7) out (the study's ablation);
* (p3): |v v'| = |w'| / w^3, so |w_{k+1} - w_k| <= a_v dl min(w_k, w_{k+1})^3. The right side is convex in w:
  the convex-concave procedure replaces w^3 by its tangent at the previous iterate (an under-estimate), so every
  iterate is feasible for the true (p3) and the objective decreases monotonically (Lipp and Boyd 2016).

The objective is exact for the interpolated plan: integral of w plus mu times the integral of (rho - rho_d)^2.
Every subproblem is a QP, built once with cvxpy parameters and re-solved (DPP) with Clarabel.
Before the solver runs, infeasibility that can be known is reported with the constraint and the arc length.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, replace

import cvxpy as cp
import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import PlanError, SolverError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.onboard import swarm_area
from vtube_planning.params import PlanningOptions, SwarmParams
from vtube_planning.planning.banded_qp import BandedPlanner
from vtube_planning.planning.density import footprint
from vtube_planning.planning.plan import (
    RHO_EPSILON,
    Plan,
    certify,
    curvature_speed_limit,
    initial_conditions,
    objective_terms,
)

FloatArray = NDArray[np.float64]

SUBSAMPLES = 20
"""Samples per grid interval used to bound curvature and width ratios over the interval."""
MAX_INTERVALS = 20_000
"""The finest grid planned: 20,000 intervals (a 0.003 m step on scenes A-D, whose default grid has 240)."""
SOLVER_OPTIONS: dict[str, float] = {}
"""Clarabel options (its defaults suffice: the constraints are normalised to order one)."""


@dataclass(frozen=True)
class Problem:
    """The discretised planning problem: grid, interval-wise data, boundary values, a feasible start."""

    tube: VirtualTube
    swarm: SwarmParams
    options: PlanningOptions
    l_m: FloatArray
    speed_cap_mps: FloatArray
    width_ratio: FloatArray
    v0_mps: float
    rho0_per_m2: float
    w_start: FloatArray
    rho_start: FloatArray

    @property
    def dl_m(self) -> FloatArray:
        """Lengths of the grid intervals, (K,)."""
        return np.diff(self.l_m)


def uniform_grid(length_m: float, step_m: float) -> FloatArray:
    """The planning grid: equal intervals of at most ``step_m`` from 0 to ``length_m`` (or :class:`PlanError`)."""
    n_int = max(2, math.ceil(length_m / step_m - 1e-9))
    if n_int > MAX_INTERVALS:
        msg = (
            f'a grid step of {step_m:g} m makes {n_int:,} intervals on this {length_m:g} m tube, more '
            f'than the {MAX_INTERVALS:,} the planner takes (each is a few variables and constraints of every QP); '
            f'use a grid step of at least {length_m / MAX_INTERVALS:.3g} m.'
        )
        raise PlanError(msg)
    return np.linspace(0.0, length_m, n_int + 1)


def discretise(
    tube: VirtualTube, swarm: SwarmParams, options: PlanningOptions, l_m: FloatArray | None = None
) -> Problem:
    """Build the grid and the interval-wise data, and prove feasibility (or raise :class:`PlanError`).

    The grid is ``options.grid_step_m`` uniform unless ``l_m`` (increasing, from 0 to the tube's length) is given.

    The slowest admissible speed profile (decelerate at a_v from v_0 down to v_min) and the fastest admissible
    expansion along it (density falling at a_rho until rho_epsilon) are the most permissive choices for every
    other constraint; if they violate one, the problem is infeasible there, and the message says where.
    """
    length = tube.length_m
    if l_m is None:
        l_m = uniform_grid(length, options.grid_step_m)
    n_int = l_m.size - 1
    sub = np.linspace(l_m[:-1], l_m[1:], SUBSAMPLES + 1, axis=1)  # (K, S+1) samples of each interval
    inside = tube.center.breakpoints[(tube.center.breakpoints > 0) & (tube.center.breakpoints < length)]
    limit_sub = curvature_speed_limit(tube, swarm, sub.ravel()).reshape(sub.shape).min(axis=1)
    if inside.size:  # curvature jumps at the joints of arcs: include both sides
        joint_k = np.clip(np.searchsorted(l_m, inside) - 1, 0, n_int - 1)
        eps = 1e-9 * max(1.0, length)
        joint = np.minimum(
            curvature_speed_limit(tube, swarm, inside - eps), curvature_speed_limit(tube, swarm, inside + eps)
        )
        np.minimum.at(limit_sub, joint_k, joint)
    interval_cap = np.minimum(limit_sub, swarm.v_max_mps)
    speed_cap = np.minimum(np.concatenate([interval_cap, [np.inf]]), np.concatenate([[np.inf], interval_cap]))
    lam = tube.half_width(sub.ravel())
    lam_ahead = tube.half_width(sub.ravel() + options.lookahead_m)
    width_ratio = np.abs(lam / lam_ahead - 1.0).reshape(sub.shape).max(axis=1)

    v0, rho0 = initial_conditions(swarm, options)
    _check_boundary_values(swarm, v0, rho0, float(speed_cap[0]))
    low = np.flatnonzero(speed_cap < swarm.v_min_mps * (1 - 1e-12))
    if low.size:
        k = int(low[0])
        msg = (
            f'(p4) is incompatible with (p2) at l = {l_m[k]:.3f} m: the curvature limit sqrt(a_n r_t) = '
            f'{speed_cap[k]:.4g} m/s is below v_min = {swarm.v_min_mps:g} m/s (r_t = {speed_cap[k] ** 2 / swarm.a_n_mps2:.4g} m); '
            f'widen the turn to r_t >= v_min^2 / a_n = {swarm.v_min_mps**2 / swarm.a_n_mps2:.4g} m or lower v_min.'
        )
        raise PlanError(msg)
    dl = np.diff(l_m)
    w_start = np.empty_like(l_m)
    w_start[0] = 1.0 / v0
    for k in range(n_int):  # decelerate as hard as (p3) allows, |dw| <= a_v dl w_k^3 while w increases
        w_start[k + 1] = min(1.0 / swarm.v_min_mps, w_start[k] + swarm.a_v_mps2 * dl[k] * w_start[k] ** 3)
    too_fast = np.flatnonzero(w_start * speed_cap < 1.0 - 1e-12)
    if too_fast.size:
        k = int(too_fast[0])
        msg = (
            f'(p3) and (p4) conflict at l = {l_m[k]:.3f} m: starting at v_0 = {v0:g} m/s and braking at '
            f'a_v = {swarm.a_v_mps2:g} m/s^2 the swarm still moves at {1 / w_start[k]:.4g} m/s where the curvature '
            f'allows {speed_cap[k]:.4g} m/s; start slower (planning v0_mps) or move the turn further in.'
        )
        raise PlanError(msg)
    rho_start = _fastest_expansion(swarm, rho0, w_start, dl)
    problem = Problem(tube, swarm, options, l_m, speed_cap, width_ratio, v0, rho0, w_start, rho_start)
    if options.predictive_model == 'local_width':
        _check_local_width(problem)
    return problem


REPAIRS = 20
"""Passes that slow the fastest admissible profile where (p7) needs it, before the slowest start is used instead."""


def fastest_admissible(problem: Problem) -> tuple[FloatArray, FloatArray] | None:
    """A start near the optimum for the convex-concave procedure, or None where it cannot be had.

    The fastest speed profile that (p2)-(p4) admit, as in time-optimal path parameterisation: from v_0, accelerate
    at a_v up to the caps, and brake at a_v in time for each; with the density falling along it as fast as (p6)
    allows. Where that is too fast for the local-width (p7), w >= ratio max(rho) / (a_rho dl_p), the speed cap is
    lowered to what (p7) asks and the profile recomputed, for at most ``REPAIRS`` passes. Every constraint then
    holds, so the procedure may start there. The rigid-shift (p7) is not checked here: it starts from the slowest
    profile, as does a problem whose repairs do not settle.
    """
    swarm, options = problem.swarm, problem.options
    if options.predictive_model == 'rigid_shift':
        return None
    dl = problem.dl_m
    floor = 1.0 / problem.speed_cap_mps
    for _ in range(REPAIRS):
        w = _fastest_slowness(floor, 1.0 / problem.v0_mps, swarm.a_v_mps2 * dl)
        if w is None or w.max() > 1.0 / swarm.v_min_mps:
            return None
        rho = _fastest_expansion(swarm, problem.rho0_per_m2, w, dl)
        if options.predictive_model == 'none':
            return w, rho
        need = problem.width_ratio * np.maximum(rho[:-1], rho[1:]) / (swarm.a_rho * options.lookahead_m)
        short = need > np.minimum(w[:-1], w[1:])
        if not short.any():
            return w, rho
        floor[:-1][short] = np.maximum(floor[:-1][short], need[short])
        floor[1:][short] = np.maximum(floor[1:][short], need[short])
    return None


def _fastest_slowness(floor: FloatArray, w0: float, rate: FloatArray) -> FloatArray | None:
    """The least slowness profile with w >= ``floor``, w_0 = ``w0`` and (p3) exact: w_k - w_{k+1} <= rate_k w_{k+1}^3
    (speeding up) and w_{k+1} - w_k <= rate_k w_k^3 (slowing down), rate = a_v dl; None when w_0 cannot brake in
    time for the floor ahead."""

    def least(target: float, c: float) -> float:  # the root of x + c x^3 = target, x in (0, target]
        x = target
        for _ in range(50):
            step = (x + c * x**3 - target) / (1.0 + 3.0 * c * x**2)
            x -= step
            if abs(step) <= 1e-15 * x:
                break
        return x

    w = [float(v) for v in floor]
    rates = [float(c) for c in rate]
    w[0] = w0
    for k, c in enumerate(rates):  # accelerate as hard as (p3) allows
        w[k + 1] = max(w[k + 1], least(w[k], c))
    for k in range(len(rates) - 1, -1, -1):  # brake in time for what lies ahead
        need = least(w[k + 1], c=rates[k])
        if k == 0 and need > w0 * (1.0 + 1e-12):
            return None
        w[k] = max(w[k], need) if k else w0
    return np.array(w)


def _check_boundary_values(swarm: SwarmParams, v0: float, rho0: float, cap0: float) -> None:
    if not swarm.v_min_mps <= v0 <= swarm.v_max_mps:
        msg = f'(p2) fails at l = 0: v0_mps = {v0:g} lies outside [v_min, v_max] = [{swarm.v_min_mps:g}, {swarm.v_max_mps:g}].'
        raise PlanError(msg)
    if v0 > cap0 * (1 + 1e-12):
        msg = f'(p4) fails at l = 0: v0_mps = {v0:g} exceeds the curvature limit {cap0:.4g} m/s at the entrance.'
        raise PlanError(msg)
    if not RHO_EPSILON <= rho0 <= swarm.rho_max_per_m2:
        msg = (
            f'(p5) fails at l = 0: the initial density {rho0:g} robots/m^2 lies outside [{RHO_EPSILON:g}, '
            f'rho_max = {swarm.rho_max_per_m2:g}]; set planning rho0_per_m2 or raise rho_max_per_m2.'
        )
        raise PlanError(msg)


def _fastest_expansion(swarm: SwarmParams, rho0: float, w: FloatArray, dl: FloatArray) -> FloatArray:
    """Density falling as fast as (p6) allows along the slowness profile w, down to rho_epsilon."""
    rho = np.empty_like(w)
    rho[0] = rho0
    step = swarm.a_rho * dl * np.minimum(w[:-1], w[1:])
    for k in range(w.size - 1):
        rho[k + 1] = max(RHO_EPSILON, rho[k] - step[k])
    return rho


def _check_local_width(problem: Problem) -> None:
    swarm, options = problem.swarm, problem.options
    budget = swarm.a_rho * options.lookahead_m * np.minimum(problem.w_start[:-1], problem.w_start[1:])
    need = problem.width_ratio * np.maximum(problem.rho_start[:-1], problem.rho_start[1:])
    bad = np.flatnonzero(need > budget * (1 + 1e-12))
    if bad.size:
        k = int(bad[0])
        msg = (
            f'(p7) cannot hold at l = {problem.l_m[k]:.3f} m: even at v_min, expanding as fast as (p6) allows, the '
            f'density {max(problem.rho_start[k], problem.rho_start[k + 1]):.4g} robots/m^2 meets a width ratio '
            f'{problem.width_ratio[k]:.3g} over the look-ahead {options.lookahead_m:g} m; start at a lower density, '
            'make the narrowing start later or more gradual, or lengthen lookahead_m.'
        )
        raise PlanError(msg)


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
        self.footprint_gap = None
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
        self.cvx = cp.Problem(cp.Minimize(time_term + density_term), cons)
        self.value = math.nan

    def set_tangent(self, w_bar: FloatArray, rho_bar: FloatArray) -> None:
        swarm, options = self.problem.swarm, self.problem.options
        dl = self.problem.dl_m
        self.inv_scale['left'].value = 1.0 / (swarm.a_v_mps2 * dl * w_bar[:-1] ** 3)
        self.inv_scale['right'].value = 1.0 / (swarm.a_v_mps2 * dl * w_bar[1:] ** 3)
        self.slope.value = 3.0 / w_bar
        if self.footprint_gap is not None:
            back, front = footprint(self.problem.tube, self.problem.l_m, rho_bar, swarm.n_robots)
            shifted = swarm_area(self.problem.tube, back + options.lookahead_m, front + options.lookahead_m, 0.0)
            gap = shifted - swarm_area(self.problem.tube, back, front, 0.0)
            self.footprint_gap.value = gap
            self.footprint_root.value = np.sqrt(np.abs(gap))

    def solve(self) -> tuple[FloatArray, FloatArray]:
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


STARTS = ('fastest', 'slowest')
"""Where the convex-concave procedure may start (``plan_convex``'s ``start``)."""
FORMULATIONS = ('banded', 'cvxpy')
"""How each convex subproblem is solved: the banded interior-point solver of :mod:`.banded_qp` (the linear
readings of (p7); the rigid shift, a cone, always goes to cvxpy), or the cvxpy reference formulation."""


def plan_convex(
    tube: VirtualTube,
    swarm: SwarmParams,
    options: PlanningOptions,
    *,
    scene: str = '',
    max_iterations: int = 60,
    rtol: float = 1e-9,
    formulation: str = 'banded',
    start: str = 'fastest',
    start_m: float = 0.0,
) -> Plan:
    """Plan speed and density by the convex-concave procedure on the slowness form.

    With ``options.refinement`` > 1 the plan on the uniform grid is followed by a second one on a grid whose
    intervals where a rate or curvature constraint binds ((p3), (p4), (p6), (p7)) are split into that many: the
    first plan is feasible on the finer grid and starts the second, which can only be faster.

    Parameters
    ----------
    max_iterations
        Upper bound on convex-concave iterations (per grid).
    rtol
        Stop when the objective improves by less than this, relative.
    formulation
        One of ``FORMULATIONS``. The banded solver falls back to cvxpy if it ever fails (``plan.extra``
        records the formulation that solved).
    start
        Where the convex-concave procedure starts: ``'fastest'``, the fastest profile every constraint admits
        (near the optimum: 2-5 iterations), where it can be had, else the slowest; ``'slowest'``, always the
        slowest admissible profile (6-7 iterations; the benchmark's reference run). ``plan.extra`` records it.
    start_m
        Plan the tube from this arc length on (replanning, :func:`replan`); 0 plans it all.

    Raises
    ------
    PlanError
        When the problem is infeasible; the message names the constraint and the arc length.
    SolverError
        When the solver fails on a subproblem known to be feasible.
    """
    if formulation not in FORMULATIONS:
        msg = f'formulation must be one of {FORMULATIONS}; got {formulation!r}.'
        raise ValueError(msg)
    if start not in STARTS:
        msg = f'start must be one of {STARTS}; got {start!r}.'
        raise ValueError(msg)
    started = time.perf_counter()
    grid = start_m + uniform_grid(tube.length_m - start_m, options.grid_step_m)
    problem = discretise(tube, swarm, options, grid)
    begin = fastest_admissible(problem) if start == 'fastest' else None
    started_from = 'slowest' if begin is None else 'fastest'
    w, rho, status, iterations, used = _convex_concave(problem, begin, formulation, max_iterations, rtol)
    if options.refinement > 1:
        probe = make_plan(
            tube,
            swarm,
            options,
            grid,
            1.0 / w,
            rho,
            method='convex',
            status=status,
            iterations=iterations,
            solve_time_s=0.0,
            scene=scene,
        )
        fine = refined_grid(grid, probe.active, options.refinement)
        problem = discretise(tube, swarm, options, fine)
        coarse = (np.interp(fine, grid, w), np.interp(fine, grid, rho))
        w, rho, status, more, used = _convex_concave(problem, coarse, formulation, max_iterations, rtol)
        iterations += more
    plan = make_plan(
        tube,
        swarm,
        options,
        problem.l_m,
        1.0 / w,
        rho,
        method='convex',
        status=status,
        iterations=iterations,
        solve_time_s=time.perf_counter() - started,
        scene=scene,
    )
    plan.extra['formulation'] = used
    plan.extra['start'] = started_from
    return plan


@dataclass(frozen=True)
class SwarmState:
    """What replanning starts from: the swarm's arc length, average forward speed and density, measured now.

    Parameters
    ----------
    arc_length_m
        Where the swarm is along the tube (the mean arc length of its working robots), in [0, L).
    speed_mps
        Its average forward speed, m/s.
    density_per_m2
        Its measured density, robots/m^2.
    n_robots
        The robots still flying, when fewer than the plan was made for (a robot failed); None: the plan's swarm.
    """

    arc_length_m: float
    speed_mps: float
    density_per_m2: float
    n_robots: int | None = None


def replan(plan: Plan, state: SwarmState, tube: VirtualTube, *, formulation: str = 'banded') -> Plan:
    """Plan the rest of the tube, from ``state.arc_length_m`` to its exit, starting from the measured state.

    Same problem as ``plan`` (its swarm, options and constraints (p2)-(p7), its certificate), with the initial
    values (p2)/(p5) taken from the state. A measured speed or density outside what the constraints admit at that
    arc length (v in [v_min, min(v_max, sqrt(a_n r_t))], rho in [rho_epsilon, rho_max]) is clipped into it, so that
    the plan starts feasibly; ``plan.extra['replanned_from']`` records the state as measured and as used.

    Raises
    ------
    PlanError
        When the state cannot be flown on: the tube's rest is shorter than two grid steps, or the swarm is too fast
        to brake for a turn ahead, or the density cannot fall in time for a narrowing (the message says where).
    """
    plan.check_matches(tube, plan.swarm)
    start = float(state.arc_length_m)
    step = plan.options.grid_step_m
    if not (np.isfinite(start) and 0.0 <= start <= tube.length_m - 2.0 * step):
        msg = (
            f'cannot replan from l = {start:g} m: the rest of the {tube.length_m:g} m tube must hold at least two grid '
            f'steps of {step:g} m (replan from 0 to {tube.length_m - 2.0 * step:g} m).'
        )
        raise PlanError(msg)
    swarm = plan.swarm if state.n_robots is None else replace(plan.swarm, n_robots=state.n_robots)
    ahead = np.linspace(start, start + step, SUBSAMPLES + 1)
    top = min(swarm.v_max_mps, float(curvature_speed_limit(tube, swarm, ahead).min()))
    speed = float(np.clip(state.speed_mps, swarm.v_min_mps, top))
    density = float(np.clip(state.density_per_m2, RHO_EPSILON, swarm.rho_max_per_m2))
    options = replace(plan.options, v0_mps=speed, rho0_per_m2=density)
    rest = plan_convex(tube, swarm, options, scene=plan.scene, formulation=formulation, start_m=start)
    rest.extra['replanned_from'] = {'measured': asdict(state), 'speed_mps': speed, 'density_per_m2': density}
    return rest


def refined_grid(l_m: FloatArray, active: dict[str, NDArray[np.bool_]], factor: int) -> FloatArray:
    """``l_m`` with every interval next to a grid point where (p3), (p4), (p6) or (p7) binds split into ``factor``."""
    binds = active['p3'] | active['p4'] | active['p6'] | active['p7']
    split = binds[:-1] | binds[1:]
    parts = np.where(split, factor, 1)
    pieces = [np.linspace(a, b, count + 1)[:-1] for a, b, count in zip(l_m[:-1], l_m[1:], parts, strict=True)]
    return np.concatenate([*pieces, l_m[-1:]])


def _convex_concave(
    problem: Problem,
    start: tuple[FloatArray, FloatArray] | None,
    formulation: str,
    max_iterations: int,
    rtol: float,
) -> tuple[FloatArray, FloatArray, str, int, str]:
    """Iterate the convex subproblem from ``start`` (feasible; default the slowest profile) to convergence.

    Returns the slowness, the density, the status, the iteration count and the formulation that solved.
    """
    banded = formulation == 'banded' and problem.options.predictive_model != 'rigid_shift'
    planner: BandedPlanner | ConvexPlanner = BandedPlanner(problem) if banded else ConvexPlanner(problem)
    w_bar, rho_bar = start if start is not None else (problem.w_start, problem.rho_start)
    previous = math.inf
    status = 'iteration limit'
    iterations = 0
    for iterations in range(1, max_iterations + 1):  # the final count is reported below
        planner.set_tangent(w_bar, rho_bar)
        try:
            w_bar, rho_bar = planner.solve()
        except SolverError:
            if not banded:
                raise
            return _convex_concave(problem, start, 'cvxpy', max_iterations, rtol)
        value = planner.value
        if previous - value <= rtol * max(1.0, abs(value)):
            status = 'converged'
            break
        previous = value
    return w_bar, rho_bar, status, iterations, 'banded' if banded else 'cvxpy'


def make_plan(
    tube: VirtualTube,
    swarm: SwarmParams,
    options: PlanningOptions,
    l_m: FloatArray,
    speed: FloatArray,
    density: FloatArray,
    *,
    method: str,
    status: str,
    iterations: int,
    solve_time_s: float,
    scene: str,
) -> Plan:
    """Wrap planned samples into a :class:`Plan` with its certificate, active sets and objective terms."""
    certificate, active = certify(tube, swarm, options, l_m, speed, density)
    objective = objective_terms(l_m, speed, density, swarm, options)
    return Plan(
        l_m=l_m,
        speed_mps=speed,
        density_per_m2=density,
        half_width_m=np.asarray(tube.half_width(l_m)),
        speed_limit_mps=curvature_speed_limit(tube, swarm, l_m),
        time_s=objective['time_s'],
        objective=objective,
        certificate=certificate,
        active=active,
        method=method,
        status=status,
        iterations=iterations,
        solve_time_s=solve_time_s,
        scene=scene,
        swarm=swarm,
        options=options,
        tube_hash=tube.fingerprint(),
    )
