"""The banded interior-point planner against the cvxpy reference formulation, and grid refinement."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from robotarium_exp.scene import load_scene
from tests.support.plans import assert_same_plan
from vtube_planning.errors import PlanError, SolverError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.scene import list_scenes
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.params import PlanningOptions, SwarmParams
from vtube_planning.planning import banded_qp
from vtube_planning.planning.banded_qp import BandedPlanner
from vtube_planning.planning.cvxpy_qp import ConvexPlanner
from vtube_planning.planning.planner import plan_convex
from vtube_planning.planning.problem import discretise


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
    (they fell back to cvxpy): the best iterate within STALLED_TOLERANCE is the reference's plan. The stall needs
    the scenes' former 0.7 m look-ahead: with today's 1.3 m (narrowing, formation and band) both grids converge."""
    scene = load_scene(name)
    options = replace(scene.planning, grid_step_m=step_m, lookahead_m=0.7)
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
