"""Speed and density planning (paper (p1)-(p8)) by the convex-concave procedure on the slowness form.

The problem is discretised on an arc-length grid (`problem`); (p3), the one non-convex constraint,
|w'| <= a_v w^3, is convexified by replacing w^3 with its tangent at the previous iterate (an under-estimate), so
that every iterate is feasible for the true (p3) and the objective decreases monotonically (Lipp and Boyd 2016,
``docs/theory.md`` §8.1). Each convex subproblem is solved by `banded_qp`, or by the cvxpy reference
(`cvxpy_qp`). Planned for the last robot out (``objective = 'last_out'``), the objective's non-convex exit term is
replaced by a convex majorant at the previous iterate (`last_out`, §8.7), kept only where it lies above the term. [`replan`][vtube_planning.planning.planner.replan] plans the rest of a tube from a measured state.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import PlanError, SolverError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.params import PlanningOptions, SwarmParams
from vtube_planning.planning.banded_qp import BandedPlanner
from vtube_planning.planning.constraints import RHO_EPSILON, certify, curvature_speed_limit, planned_limits
from vtube_planning.planning.fastest_start import fastest_admissible
from vtube_planning.planning.last_out import GROWTH, MAX_TRIES, ExitTerm, half_extent_weight
from vtube_planning.planning.plan import (
    Formulation,
    Plan,
    ReplanStart,
    SolveRecord,
    Start,
    Status,
    SwarmState,
    make_plan,
)
from vtube_planning.planning.problem import SUBSAMPLES, Problem, discretise, refined_grid, uniform_grid

if TYPE_CHECKING:
    from vtube_planning.planning.cvxpy_qp import ConvexPlanner

FloatArray = NDArray[np.float64]

STARTS: tuple[Start, ...] = ('fastest', 'slowest')
"""Where the convex-concave procedure may start (``plan_convex``'s ``start``)."""
FORMULATIONS: tuple[Formulation, ...] = ('banded', 'cvxpy')
"""How each convex subproblem is solved: the banded interior-point solver of `banded_qp` (the linear
readings of (p7); the rigid shift, a cone, always goes to cvxpy), or the cvxpy reference formulation."""


def plan_convex(
    tube: VirtualTube,
    swarm: SwarmParams,
    options: PlanningOptions,
    *,
    scene: str = '',
    max_iterations: int = 60,
    rtol: float = 1e-9,
    formulation: Formulation = 'banded',
    start: Start = 'fastest',
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
        One of ``FORMULATIONS``. The banded solver falls back to cvxpy if it ever fails (``plan.solved`` records
        the formulation that solved).
    start
        Where the convex-concave procedure starts: ``'fastest'``, the fastest profile every constraint admits,
        where it can be had, else the slowest; ``'slowest'``, always the slowest admissible profile.
        ``plan.solved`` records it.
    start_m
        Plan the tube from this arc length on (replanning, [`replan`][vtube_planning.planning.planner.replan]); 0 plans
        it all.

    Raises
    ------
    PlanError
        When the problem is infeasible; the message names the constraint and the arc length.
    SolverError
        When the solver fails on a subproblem known to be feasible.
    """
    _check_choice('formulation', formulation, FORMULATIONS)
    _check_choice('start', start, STARTS)
    started = time.perf_counter()
    grid = start_m + uniform_grid(tube.length_m - start_m, options.grid_step_m)
    problem = discretise(tube, swarm, options, grid)
    begin = fastest_admissible(problem) if start == 'fastest' else None
    run = _convex_concave(problem, begin, formulation, max_iterations, rtol)
    if options.refinement > 1:
        problem, run = _refined(problem, run, formulation, max_iterations, rtol)
    solved = SolveRecord(
        'convex',
        run.status,
        run.iterations,
        time.perf_counter() - started,
        formulation=run.formulation,
        start='slowest' if begin is None else 'fastest',
    )
    return make_plan(tube, swarm, options, problem.l_m, 1.0 / run.w, run.rho, solved=solved, scene=scene)


def replan(plan: Plan, state: SwarmState, tube: VirtualTube, *, formulation: Formulation = 'banded') -> Plan:
    """Plan the rest of the tube, from ``state.arc_length_m`` to its exit, starting from the measured state.

    Same problem as ``plan`` (its swarm, options and constraints (p2)-(p7), its certificate), with the initial
    values (p2)/(p5) taken from the state. A measured speed or density outside what the constraints admit at that
    arc length (v in [v_min, min(v_max, sqrt(a_n r_t))], rho in [rho_epsilon, rho_max]) is clipped into it, so that
    the plan starts feasibly; ``plan.solved.replanned_from`` records the state as measured and as used.

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
    top = min(swarm.v_max_mps, float(curvature_speed_limit(tube, planned_limits(swarm, plan.options), ahead).min()))
    speed = float(np.clip(state.speed_mps, swarm.v_min_mps, top))
    density = float(np.clip(state.density_per_m2, RHO_EPSILON, swarm.rho_max_per_m2))
    options = replace(plan.options, v0_mps=speed, rho0_per_m2=density)
    rest = plan_convex(tube, swarm, options, scene=plan.scene, formulation=formulation, start_m=start)
    return replace(rest, solved=replace(rest.solved, replanned_from=ReplanStart(state, speed, density)))


def _check_choice(name: str, value: str, choices: tuple[str, ...]) -> None:
    """ValueError unless ``value`` is one of ``choices``."""
    if value not in choices:
        msg = f'{name} must be one of {choices}; got {value!r}.'
        raise ValueError(msg)


@dataclass(frozen=True)
class _Run:
    """The convex-concave procedure's result: slowness, density, status, iterations, the formulation that solved."""

    w: FloatArray
    rho: FloatArray
    status: Status
    iterations: int
    formulation: Formulation


def _refined(
    problem: Problem, run: _Run, formulation: Formulation, max_iterations: int, rtol: float
) -> tuple[Problem, _Run]:
    """The problem on the grid refined where ``run``'s plan binds a rate or curvature constraint, and the procedure
    run there from that plan (iterations of both runs counted)."""
    grid = problem.l_m
    _, active = certify(problem.tube, problem.swarm, problem.options, grid, 1.0 / run.w, run.rho)
    fine = refined_grid(grid, active, problem.options.refinement)
    finer = discretise(problem.tube, problem.swarm, problem.options, fine)
    coarse = (np.interp(fine, grid, run.w), np.interp(fine, grid, run.rho))
    more = _convex_concave(finer, coarse, formulation, max_iterations, rtol)
    return finer, replace(more, iterations=run.iterations + more.iterations)


def _reference_planner(problem: Problem) -> ConvexPlanner:
    """The cvxpy formulation of ``problem`` (cvxpy is imported here, when it is needed: it takes about half a
    second)."""
    from vtube_planning.planning.cvxpy_qp import ConvexPlanner

    return ConvexPlanner(problem)


def _convex_concave(
    problem: Problem,
    start: tuple[FloatArray, FloatArray] | None,
    formulation: Formulation,
    max_iterations: int,
    rtol: float,
) -> _Run:
    """Iterate the convex subproblem from ``start`` (feasible; default the slowest profile) to convergence."""
    banded = formulation == 'banded' and problem.options.predictive_model != 'rigid_shift'
    planner = BandedPlanner(problem) if banded else _reference_planner(problem)
    w_bar, rho_bar = start if start is not None else (problem.w_start, problem.rho_start)
    term = _exit_term(problem)
    previous = math.inf
    status: Status = 'iteration limit'
    iterations = 0
    for iterations in range(1, max_iterations + 1):  # the final count is reported below
        planner.set_tangent(w_bar, rho_bar)
        try:
            if term is None:
                w_bar, rho_bar = planner.solve()
                value = planner.value
            else:
                step = _majorised_step(planner, term, w_bar, rho_bar)
                if step is None:  # no step lowers the objective: the iterate is stationary
                    status = 'converged'
                    break
                w_bar, rho_bar, value = step
        except SolverError:
            if not banded:
                raise
            return _convex_concave(problem, start, 'cvxpy', max_iterations, rtol)
        if previous - value <= rtol * max(1.0, abs(value)):
            status = 'converged'
            break
        previous = value
    return _Run(w_bar, rho_bar, status, iterations, 'banded' if banded else 'cvxpy')


def _exit_term(problem: Problem) -> ExitTerm | None:
    """The last-robot-out exit term of the problem's objective (None for the centre's time, the paper's (p1))."""
    if problem.options.objective != 'last_out':
        return None
    return ExitTerm(half_extent_weight(problem.tube, problem.swarm, float(problem.l_m[-1])))


def _majorised_step(
    planner: BandedPlanner | ConvexPlanner, term: ExitTerm, w_bar: FloatArray, rho_bar: FloatArray
) -> tuple[FloatArray, FloatArray, float] | None:
    """One step of the procedure with the exit term majorised at (w_bar, rho_bar) (``last_out``): the step and the
    true objective there (the subproblem's, the model replaced by the term). A step where the model does not lie
    above the term is solved again with a larger curvature; None after ``MAX_TRIES`` (the iterate stays)."""
    for tries in range(MAX_TRIES):
        model = term.model(float(w_bar[-1]), float(rho_bar[-1]), GROWTH**tries)
        planner.set_exit_model(model)
        w, rho = planner.solve()
        ends = float(w[-1]), float(rho[-1])
        if term.lies_above(model, *ends):
            return w, rho, planner.value - model.value(*ends) + term.value(*ends)
    return None
