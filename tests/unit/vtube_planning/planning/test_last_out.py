"""The last-robot-out objective: its terms, its convex model, the two solvers plan for plan, a brute-force oracle."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scipy.optimize import minimize

from tests.support.plans import assert_same_plan
from vtube_planning.errors import ParamsError, PlanError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.scene import load_scene
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.params import PlanningOptions, SwarmParams
from vtube_planning.planning.constraints import RHO_EPSILON, objective_terms
from vtube_planning.planning.last_out import ExitTerm, half_extent_weight, last_out_terms
from vtube_planning.planning.plan import SwarmState
from vtube_planning.planning.planner import plan_convex, replan
from vtube_planning.planning.polynomial import plan_polynomial


def straight(length_m: float, half_width_m: float) -> VirtualTube:
    center = ArcPath((ArcPiece(length_m),))
    return VirtualTube(center, WidthProfile(half_width_m, (WidthPart('constant', length_m),)))


def test_half_extent_is_the_swarm_area_spread_over_the_width() -> None:
    tube, swarm = straight(10.0, 1.5), SwarmParams(n_robots=30)
    c = half_extent_weight(tube, swarm, 4.0)
    rho = 0.25
    extent = 2.0 * c / rho  # the whole column
    assert extent * 2.0 * 1.5 * rho == pytest.approx(30)  # holds the N robots at density rho over the width 2 lambda
    terms = last_out_terms(tube, swarm, np.array([0.0, 10.0]), np.array([2.0, 4.0]), np.array([0.5, rho]))
    assert terms['entry_s'] == pytest.approx(30 / (4 * 1.5) / (2.0 * 0.5))
    assert terms['exit_s'] == pytest.approx(c / rho / 4.0)


def test_gradient_matches_finite_differences() -> None:
    term = ExitTerm(5.0)
    w, rho, h = 0.3, 0.17, 1e-6
    gw, gr = term.gradient(w, rho)
    assert gw == pytest.approx((term.value(w + h, rho) - term.value(w - h, rho)) / (2 * h), rel=1e-8)
    assert gr == pytest.approx((term.value(w, rho + h) - term.value(w, rho - h)) / (2 * h), rel=1e-8)


@pytest.mark.parametrize(('w_bar', 'rho_bar'), [(0.2, 0.2), (0.5, 0.05), (0.25, 0.9)])
def test_model_touches_the_term_and_lies_above_it_near_the_iterate(w_bar: float, rho_bar: float) -> None:
    term = ExitTerm(4.0)
    model = term.model(w_bar, rho_bar)
    assert model.value(w_bar, rho_bar) == pytest.approx(term.value(w_bar, rho_bar), rel=1e-12)
    h = 1e-6  # the model's gradient is the term's
    for dw, dr in ((h, 0.0), (0.0, h)):
        slope = (model.value(w_bar + dw, rho_bar + dr) - model.value(w_bar - dw, rho_bar - dr)) / (2 * h)
        assert slope == pytest.approx(term.gradient(w_bar, rho_bar)[0 if dw else 1], rel=1e-6)
    angles = np.linspace(0.0, 2 * np.pi, 64, endpoint=False)
    for radius in (1e-3, 1e-2):
        for a in angles:
            w, rho = w_bar * (1 + radius * np.cos(a)), rho_bar * (1 + radius * np.sin(a))
            assert term.lies_above(model, w, rho)


def test_unknown_objective_is_refused() -> None:
    with pytest.raises(ParamsError, match="objective must be one of \\('centre', 'last_out'\\); got 'first'"):
        PlanningOptions(objective='first')


def test_polynomial_method_refuses_the_last_out_objective() -> None:
    scene = load_scene('A')
    with pytest.raises(PlanError, match="centre's time only"):
        plan_polynomial(scene.tube, scene.swarm, replace(scene.planning, objective='last_out'))


def test_terms_need_the_tube_for_the_last_out_objective() -> None:
    options = PlanningOptions(objective='last_out')
    ones = np.ones(3)
    with pytest.raises(ValueError, match='needs the tube'):
        objective_terms(np.arange(3.0), ones, ones, SwarmParams(), options)


@pytest.mark.parametrize('n_robots', [20, 80])
@pytest.mark.parametrize('name', ['C', 'D'])
def test_banded_solver_plans_what_the_cvxpy_reference_plans(name: str, n_robots: int) -> None:
    scene = load_scene(name)
    swarm = replace(scene.swarm, n_robots=n_robots)
    options = replace(scene.planning, objective='last_out')
    banded = plan_convex(scene.tube, swarm, options)
    reference = plan_convex(scene.tube, swarm, options, formulation='cvxpy')
    assert_same_plan(banded, reference)
    assert banded.solved.iterations == reference.solved.iterations  # the same path of majorised steps
    centre = plan_convex(scene.tube, swarm, scene.planning)
    # the objective is J plus the half-extents; planned for it, the plan's own J is lower than the centre plan's
    assert (
        banded.objective['total']
        < objective_terms(centre.l_m, centre.speed_mps, centre.density_per_m2, swarm, options, scene.tube)['total']
    )
    assert (
        banded.objective['exit_s']
        < last_out_terms(scene.tube, swarm, centre.l_m, centre.speed_mps, centre.density_per_m2)['exit_s']
    )


def test_plan_is_the_optimum_of_brute_force_and_slsqp_on_a_two_interval_tube() -> None:
    """Two intervals of 1 m, (p7) off: w_0, rho_0 fixed, four unknowns (w_1, w_2, rho_1, rho_2). The exit term pulls
    the exit density up, which (p6) lets rise only with the time spent (a_rho dl w), against the time term. No
    feasible point of a grid over the whole box beats the plan (a global check), and SLSQP on the true, non-convex
    problem from many starts finds nothing better and reaches it (a tight one)."""
    tube, swarm = straight(2.0, 1.0), SwarmParams(n_robots=80)
    options = PlanningOptions(grid_step_m=1.0, predictive_model='none', rho0_per_m2=0.2, objective='last_out')
    plan = plan_convex(tube, swarm, options)
    w0, rho0, c = 1.0 / swarm.v_min_mps, 0.2, half_extent_weight(tube, swarm, 2.0)
    a_v, a_rho, rho_d = swarm.a_v_mps2, swarm.a_rho, swarm.rho_d_per_m2

    def j_of(x: np.ndarray) -> np.ndarray:
        w1, w2, r1, r2 = x
        e0, e1, e2 = rho0 - rho_d, r1 - rho_d, r2 - rho_d
        density = (e0**2 + e0 * e1 + e1**2 + e1**2 + e1 * e2 + e2**2) / 3.0
        return 0.5 * w0 + w1 + 0.5 * w2 + density + c * w0 / rho0 + c * w2 / r2  # type: ignore[no-any-return]

    def slack(x: np.ndarray) -> np.ndarray:
        """(p3) and (p6) on both intervals as g(x) >= 0 (rounded minima kept smooth enough for SLSQP)."""
        w1, w2, r1, r2 = x
        return np.array(
            [
                a_v * np.minimum(w0, w1) ** 3 - np.abs(w1 - w0),
                a_v * np.minimum(w1, w2) ** 3 - np.abs(w2 - w1),
                a_rho * np.minimum(w0, w1) - np.abs(r1 - rho0),
                a_rho * np.minimum(w1, w2) - np.abs(r2 - r1),
            ]
        )

    low = np.array([1 / swarm.v_max_mps, 1 / swarm.v_max_mps, RHO_EPSILON, RHO_EPSILON])
    high = np.array([w0, w0, swarm.rho_max_per_m2, swarm.rho_max_per_m2])
    x_plan = np.array([1 / plan.speed_mps[1], 1 / plan.speed_mps[2], *plan.density_per_m2[1:]])
    j_plan = plan.objective['total']
    assert j_plan == pytest.approx(float(j_of(x_plan)), rel=1e-12)
    grid = np.stack(np.meshgrid(*(np.linspace(a, b, 31) for a, b in zip(low, high, strict=True))), axis=0)
    points = grid.reshape(4, -1)
    on_grid = j_of(points)[np.all(slack(points) >= 0.0, axis=0)]
    assert on_grid.size > 100 and j_plan <= on_grid.min()
    rng = np.random.default_rng(0)
    found = []
    for start in rng.uniform(low, high, size=(30, 4)):
        fit = minimize(
            j_of,
            start,
            method='SLSQP',
            bounds=list(zip(low, high, strict=True)),
            constraints=[{'type': 'ineq', 'fun': slack}],
            options={'ftol': 1e-12, 'maxiter': 500},
        )
        if fit.success and np.all(slack(fit.x) >= -1e-9):
            found.append(fit.fun)
    assert len(found) >= 5
    assert j_plan <= min(found) + 1e-7 * j_plan
    assert min(found) <= j_plan * (1 + 1e-6)  # SLSQP reaches the plan's optimum
    assert plan.density_per_m2[2] > plan.density_per_m2[1] > rho0  # the exit term raised the density


def test_replanning_the_rest_keeps_the_objective_and_the_exit() -> None:
    """The rest of a last-out plan, replanned from its own state at 20 m, ends as it does (Bellman): the same exit
    density and exit term, and its entry term is the swarm's half-extent where it starts."""
    scene = load_scene('C')
    plan = plan_convex(scene.tube, scene.swarm, replace(scene.planning, objective='last_out'))
    k = int(np.searchsorted(plan.l_m, 20.0))
    state = SwarmState(float(plan.l_m[k]), float(plan.speed_mps[k]), float(plan.density_per_m2[k]))
    rest = replan(plan, state, scene.tube)
    assert rest.options.objective == 'last_out' and rest.max_violation <= 1e-8
    assert rest.objective['exit_s'] == pytest.approx(plan.objective['exit_s'], rel=1e-6)
    assert rest.density_per_m2[-1] == pytest.approx(plan.density_per_m2[-1], rel=1e-6)
    c = half_extent_weight(scene.tube, scene.swarm, state.arc_length_m)
    assert rest.objective['entry_s'] == pytest.approx(c / (state.speed_mps * state.density_per_m2), rel=1e-12)
