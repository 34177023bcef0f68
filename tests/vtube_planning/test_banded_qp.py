"""The banded interior-point planner against the cvxpy reference formulation, and grid refinement."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from vtube_planning import (
    ArcPath,
    ArcPiece,
    PlanningOptions,
    SwarmParams,
    VirtualTube,
    WidthPart,
    WidthProfile,
    list_scenes,
    load_scene,
)
from vtube_planning.errors import ParamsError, PlanError, SolverError
from vtube_planning.planning import banded_qp
from vtube_planning.planning.banded_qp import BandedPlanner
from vtube_planning.planning.constraints import certify
from vtube_planning.planning.cvxpy_qp import ConvexPlanner
from vtube_planning.planning.fastest_start import fastest_admissible
from vtube_planning.planning.plan import Plan
from vtube_planning.planning.planner import plan_convex
from vtube_planning.planning.problem import discretise, refined_grid, uniform_grid

CERTIFICATE = 1e-8  # the bound for the banded planner


def assert_same_plan(banded: Plan, reference: Plan, *, density: bool = True) -> None:
    """Same objective to 1e-8 relative (the solvers' tolerances), same profiles, banded certified below 1e-8.

    The density is only weakly pinned (its term of (p1) is worth about 0.01 s), so the reference's own solver
    tolerance (1e-8 on the objective) leaves it accurate to about 1e-5: it is compared to 1e-4 of rho_max, and not
    at all (``density=False``) when its weight is zero and any feasible density is optimal.
    """
    assert banded.solved.formulation == 'banded' and reference.solved.formulation == 'cvxpy'
    j = reference.objective['total']
    assert banded.objective['total'] == pytest.approx(j, rel=1e-8)
    np.testing.assert_array_equal(banded.l_m, reference.l_m)
    np.testing.assert_allclose(banded.speed_mps, reference.speed_mps, rtol=1e-5)
    if density:
        rho_max = banded.swarm.rho_max_per_m2
        np.testing.assert_allclose(banded.density_per_m2, reference.density_per_m2, atol=1e-4 * rho_max)
    assert banded.max_violation <= CERTIFICATE


@pytest.mark.parametrize('model', ['local_width', 'none'])
@pytest.mark.parametrize('name', list_scenes())
def test_banded_solver_plans_what_the_cvxpy_reference_plans(name: str, model: str) -> None:
    scene = load_scene(name)
    options = replace(scene.planning, predictive_model=model)
    banded = plan_convex(scene.tube, scene.swarm, options)
    reference = plan_convex(scene.tube, scene.swarm, options, formulation='cvxpy')
    assert_same_plan(banded, reference)
    assert banded.solved.iterations == reference.solved.iterations  # the same convex-concave path


@pytest.mark.parametrize(('name', 'step_m'), [('robotarium_curve', 0.1), ('robotarium_trapezoid', 0.01)])
def test_a_stalled_interior_point_iteration_still_gives_the_reference_plan(name: str, step_m: float) -> None:
    """On these grids the normal matrix loses its definiteness to rounding before the residuals reach TOLERANCE
    (they fell back to cvxpy): the best iterate within STALLED_TOLERANCE is the reference's plan."""
    scene = load_scene(name)
    options = replace(scene.planning, grid_step_m=step_m)
    stalls = []
    factor = BandedPlanner._factor

    def spy(self: BandedPlanner, products: np.ndarray, weight: np.ndarray) -> np.ndarray:
        try:
            return factor(self, products, weight)
        except SolverError:
            stalls.append(self.steps)
            raise

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(BandedPlanner, '_factor', spy)
        banded = plan_convex(scene.tube, scene.swarm, options)
    assert stalls  # the case this test is about
    assert_same_plan(banded, plan_convex(scene.tube, scene.swarm, options, formulation='cvxpy'))


@pytest.mark.parametrize('seed', range(6))
def test_banded_solver_matches_the_reference_on_random_tubes_and_swarms(seed: int) -> None:
    rng = np.random.default_rng(seed)
    parts = rng.uniform([8.0, 2.0, 8.0], [15.0, 8.0, 15.0])
    kind = str(rng.choice(['smooth', 'linear']))
    width = WidthProfile(
        3.0,
        (
            WidthPart('constant', parts[0]),
            WidthPart(kind, parts[1], to_m=rng.uniform(0.8, 2.5)),
            WidthPart('constant', parts[2]),
        ),
    )
    straight, arc = rng.uniform(3.0, 6.0), rng.uniform(3.0, 8.0)
    turn = ArcPiece(arc, radius_m=rng.uniform(8.0, 30.0))
    tube = VirtualTube(ArcPath((ArcPiece(straight), turn, ArcPiece(parts.sum() - straight - arc))), width)
    swarm = SwarmParams(
        n_robots=int(rng.integers(5, 40)), a_v_mps2=rng.uniform(0.5, 3.0), a_n_mps2=rng.uniform(1.0, 4.0)
    )
    options = PlanningOptions(
        grid_step_m=rng.uniform(0.15, 0.5), density_weight=rng.choice([0.0, 1.0, 30.0]), lookahead_m=3.0
    )
    try:
        reference = plan_convex(tube, swarm, options, formulation='cvxpy')
    except PlanError:
        pytest.skip('this random problem is infeasible (reported before any solver runs)')
    assert_same_plan(plan_convex(tube, swarm, options), reference, density=options.density_weight > 0)


def test_one_subproblem_has_the_reference_optimum_from_every_convex_concave_tangent() -> None:
    scene = load_scene('C')
    problem = discretise(scene.tube, scene.swarm, scene.planning)
    banded, reference = BandedPlanner(problem), ConvexPlanner(problem)
    w, rho = problem.w_start, problem.rho_start
    for _ in range(4):
        banded.set_tangent(w, rho)
        reference.set_tangent(w, rho)
        w_b, rho_b = banded.solve()
        w, rho = reference.solve()
        assert banded.value == pytest.approx(reference.value, rel=1e-8)
        np.testing.assert_allclose(w_b, w, rtol=1e-5)
        np.testing.assert_allclose(rho_b, rho, atol=1e-4 * scene.swarm.rho_max_per_m2)


def test_warm_starts_take_fewer_interior_point_steps_than_the_first_solve() -> None:
    scene = load_scene('A')
    problem = discretise(scene.tube, scene.swarm, scene.planning)
    planner = BandedPlanner(problem)
    w, rho, steps = problem.w_start, problem.rho_start, []
    for _ in range(6):
        planner.set_tangent(w, rho)
        w, rho = planner.solve()
        steps.append(planner.steps)
    assert steps[-1] < steps[0] / 2  # near the fixed point the warm start is almost the solution


def test_a_failing_banded_solve_falls_back_to_the_reference(monkeypatch) -> None:
    scene = load_scene('C')
    expected = plan_convex(scene.tube, scene.swarm, scene.planning, formulation='cvxpy')

    def failing(self):
        raise SolverError('forced failure')

    monkeypatch.setattr(banded_qp.BandedPlanner, 'solve', failing)
    plan = plan_convex(scene.tube, scene.swarm, scene.planning)
    assert plan.solved.formulation == 'cvxpy'
    assert plan.objective['total'] == expected.objective['total']


def test_rigid_shift_is_solved_by_the_reference_and_bad_formulations_are_refused() -> None:
    scene = load_scene('A')
    rigid = plan_convex(scene.tube, scene.swarm, replace(scene.planning, predictive_model='rigid_shift'))
    assert rigid.solved.formulation == 'cvxpy'
    with pytest.raises(ValueError, match=r"formulation must be one of \('banded', 'cvxpy'\)"):
        plan_convex(scene.tube, scene.swarm, scene.planning, formulation='osqp')
    with pytest.raises(ValueError, match='linear predictive models only'):
        BandedPlanner(discretise(scene.tube, scene.swarm, replace(scene.planning, predictive_model='rigid_shift')))


# ---------------------------------------------------------------------- refinement


def test_refined_grid_splits_exactly_the_intervals_next_to_binding_points() -> None:
    l_m = np.linspace(0.0, 5.0, 6)
    none = np.zeros(6, dtype=bool)
    active = {'p3': none.copy(), 'p4': none.copy(), 'p6': none.copy(), 'p7': none.copy(), 'v_max': ~none}
    active['p3'][2] = True  # intervals 1 and 2
    active['p7'][5] = True  # interval 4
    fine = refined_grid(l_m, active, 4)
    assert set(l_m) <= set(fine) and np.all(np.diff(fine) > 0)
    np.testing.assert_allclose(np.diff(fine), [1.0] + [0.25] * 8 + [1.0] + [0.25] * 4)


def straight_time_optimum(swarm: SwarmParams, length_m: float) -> float:
    """Traversal time accelerating at v v' = a_v from v_min to v_max, then cruising: the continuum's optimum."""
    v0, v1, a = swarm.v_min_mps, swarm.v_max_mps, swarm.a_v_mps2
    ramp = (v1**2 - v0**2) / (2 * a)
    return (v1 - v0) / a + (length_m - ramp) / v1


def test_refinement_where_p3_binds_shrinks_the_gap_to_the_continuous_optimum_by_the_factor() -> None:
    swarm = SwarmParams()
    length = 30.0
    tube = VirtualTube(ArcPath((ArcPiece(length),)), WidthProfile(3.0, (WidthPart('constant', length),)))
    optimum = straight_time_optimum(swarm, length)
    gaps = {}
    for factor in (1, 8):
        plan = plan_convex(tube, swarm, PlanningOptions(grid_step_m=0.5, refinement=factor))
        assert plan.max_violation <= CERTIFICATE
        gaps[factor] = plan.time_s - optimum
        if factor > 1:  # the coarse grid's points are kept, and the refined part is where p3 binds
            assert set(uniform_grid(length, 0.5)) <= set(plan.l_m)
            fine = np.diff(plan.l_m) < 0.5 - 1e-9
            assert plan.l_m[1:][fine].max() <= (swarm.v_max_mps**2 - swarm.v_min_mps**2) / (2 * swarm.a_v_mps2) + 1.0
    assert gaps[1] > 0 and gaps[8] > 0  # certified plans cannot beat the continuum
    assert gaps[8] == pytest.approx(gaps[1] / 8, rel=0.15)  # first-order error, 8 times finer where it arises


def test_refined_plan_is_no_slower_and_the_reference_agrees_on_its_non_uniform_grid() -> None:
    scene = load_scene('C')
    options = replace(scene.planning, refinement=4)
    refined = plan_convex(scene.tube, scene.swarm, options)
    coarse = plan_convex(scene.tube, scene.swarm, scene.planning)
    assert refined.objective['total'] < coarse.objective['total']
    assert np.ptp(np.diff(refined.l_m)) > 0.1  # non-uniform
    assert_same_plan(refined, plan_convex(scene.tube, scene.swarm, options, formulation='cvxpy'))


@pytest.mark.parametrize('bad', [0, -2, 1.5, True, '4'])
def test_refinement_must_be_a_whole_number_of_at_least_one(bad: object) -> None:
    with pytest.raises(ParamsError, match='refinement must be a whole number >= 1'):
        PlanningOptions(refinement=bad)  # type: ignore[arg-type]


# ---------------------------------------------------------------------- the fastest admissible start


@pytest.mark.parametrize('model', ['local_width', 'none'])
@pytest.mark.parametrize('name', list_scenes())
def test_the_fastest_start_is_admissible_and_no_admissible_profile_is_faster(name: str, model: str) -> None:
    scene = load_scene(name)
    options = replace(scene.planning, predictive_model=model)
    problem = discretise(scene.tube, scene.swarm, options)
    start = fastest_admissible(problem)
    assert start is not None
    w, rho = start
    certificate, _ = certify(scene.tube, scene.swarm, options, problem.l_m, 1.0 / w, rho)
    assert max(certificate.values()) <= 1e-12  # every constraint holds: the procedure may start there
    plan = plan_convex(scene.tube, scene.swarm, options)
    assert np.all(1.0 / plan.speed_mps >= w * (1 - 1e-7))  # the optimal plan is admissible, hence not faster


@pytest.mark.parametrize('name', list_scenes())
def test_both_starts_reach_the_same_plan_the_fastest_in_fewer_iterations(name: str) -> None:
    scene = load_scene(name)
    fast = plan_convex(scene.tube, scene.swarm, scene.planning)
    slow = plan_convex(scene.tube, scene.swarm, scene.planning, start='slowest')
    assert (fast.solved.start, slow.solved.start) == ('fastest', 'slowest')
    assert fast.objective['total'] == pytest.approx(slow.objective['total'], rel=1e-8)
    assert fast.solved.iterations < slow.solved.iterations


def test_the_rigid_shift_reading_starts_from_the_slowest_profile_and_bad_starts_are_refused() -> None:
    scene = load_scene('C')
    rigid = plan_convex(scene.tube, scene.swarm, replace(scene.planning, predictive_model='rigid_shift'))
    assert rigid.solved.start == 'slowest'
    with pytest.raises(ValueError, match=r"start must be one of \('fastest', 'slowest'\)"):
        plan_convex(scene.tube, scene.swarm, scene.planning, start='middle')
