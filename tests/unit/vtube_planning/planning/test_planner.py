"""Speed and density planning: analytic oracles, certificates, optimality against independent solvers."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

import vtube_planning.planning.planner as planner_module
from tests.support.slsqp_reference import slsqp_plan
from vtube_planning.errors import PlanError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.scene import list_scenes, load_scene
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.params import PlanningOptions, SwarmParams
from vtube_planning.planning.constraints import initial_conditions, worst_places
from vtube_planning.planning.cvxpy_qp import ConvexPlanner
from vtube_planning.planning.plan import Plan, make_plan
from vtube_planning.planning.planner import plan_convex
from vtube_planning.planning.polynomial import plan_polynomial
from vtube_planning.planning.problem import discretise

CERTIFIED = 1e-6  # the bound on relative violations


def tube_of(center: ArcPath, half_width_m: float = 3.0) -> VirtualTube:
    return VirtualTube(center, WidthProfile(half_width_m, (WidthPart('constant', center.length_m),)))


@pytest.fixture(scope='module')
def shipped_plans() -> dict[str, Plan]:
    plans = {}
    for name in list_scenes():
        scene = load_scene(name)
        plans[name] = plan_convex(scene.tube, scene.swarm, scene.planning, scene=name)
    return plans


# ---------------------------------------------------------------------- analytic oracles


def test_straight_tube_accelerates_at_the_p3_limit_and_expands_at_the_p6_limit() -> None:
    swarm = SwarmParams()
    options = PlanningOptions(grid_step_m=0.05)
    plan = plan_convex(tube_of(ArcPath((ArcPiece(30.0),))), swarm, options)
    v0, rho0 = swarm.v_min_mps, swarm.rho_packing
    a_v, a_rho = swarm.a_v_mps2, swarm.a_rho
    l = plan.l_m
    # v v' = a_v from v0: v = sqrt(v0^2 + 2 a_v l), reaching v_max at (v_max^2 - v0^2) / (2 a_v) = 10.5 m
    analytic_v = np.minimum(np.sqrt(v0**2 + 2 * a_v * l), swarm.v_max_mps)
    assert np.all(plan.speed_mps <= analytic_v * (1 + 1e-7))  # (p3) holds in the continuum
    np.testing.assert_allclose(plan.speed_mps, analytic_v, atol=0.02)  # and the plan rides it
    assert np.all(plan.speed_mps[l > 10.6] == pytest.approx(swarm.v_max_mps, rel=1e-7))
    # d rho / dl = -a_rho / v: rho = rho0 - a_rho (sqrt(v0^2 + 2 a_v l) - v0) / a_v until rho_d
    analytic_rho = rho0 - a_rho * (np.sqrt(v0**2 + 2 * a_v * l) - v0) / a_v
    reach = l[np.argmax(analytic_rho <= swarm.rho_d_per_m2)]
    early = l < reach - 0.1
    np.testing.assert_allclose(plan.density_per_m2[early], analytic_rho[early], atol=2e-3)
    np.testing.assert_allclose(plan.density_per_m2[l > reach + 0.5], swarm.rho_d_per_m2, atol=1e-6)
    assert plan.is_certified(CERTIFIED)


@pytest.mark.parametrize('radius_m', [4.0, 9.0, 16.0])
def test_circular_tube_binds_p4_at_sqrt_an_r(radius_m: float) -> None:
    swarm = SwarmParams()
    center = ArcPath((ArcPiece(radius_m * 2.5, radius_m=radius_m),))
    plan = plan_convex(tube_of(center, 0.5 * radius_m), swarm, PlanningOptions(grid_step_m=0.1))
    limit = math.sqrt(swarm.a_n_mps2 * radius_m)
    assert plan.speed_mps.max() == pytest.approx(limit, rel=1e-7)
    settled = plan.l_m > (limit**2 - swarm.v_min_mps**2) / (2 * swarm.a_v_mps2) + 0.2
    np.testing.assert_allclose(plan.speed_mps[settled], limit, rtol=1e-7)
    assert plan.active['p4'][settled].all()
    assert plan.is_certified(CERTIFIED)


def test_first_convex_concave_iterate_is_already_feasible() -> None:
    scene = load_scene('D')
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, max_iterations=1)
    assert plan.solved.iterations == 1 and plan.solved.status == 'iteration limit'
    assert plan.is_certified(CERTIFIED)
    full = plan_convex(scene.tube, scene.swarm, scene.planning)
    assert full.objective['total'] <= plan.objective['total']  # and the procedure only improves


def test_subproblem_is_built_once_and_parameterised() -> None:
    scene = load_scene('C')
    planner = ConvexPlanner(discretise(scene.tube, scene.swarm, scene.planning))
    assert planner.cvx.is_dcp(dpp=True)  # type: ignore[call-arg]  # cvxpy's compute_once decorator hides dpp
    assert planner.cvx.is_qp()


# ---------------------------------------------------------------------- shipped scenes


@pytest.mark.parametrize('name', list_scenes())
def test_every_shipped_scene_plans_certified(name: str, shipped_plans: dict[str, Plan]) -> None:
    plan = shipped_plans[name]
    assert plan.solved.status == 'converged'
    assert plan.max_violation <= CERTIFIED, plan.certificate
    scene = load_scene(name)
    v0, rho0 = initial_conditions(scene.swarm, scene.planning)
    assert plan.speed_mps[0] == pytest.approx(v0) and plan.density_per_m2[0] == pytest.approx(rho0)


@pytest.mark.parametrize('name', ['C', 'D'])
def test_rapid_narrowing_plans_a_pre_expansion(name: str, shipped_plans: dict[str, Plan]) -> None:
    plan, tube = shipped_plans[name], load_scene(name).tube
    slope = np.abs(tube.half_width_slope(plan.l_m))
    narrowing = plan.l_m[slope > 1e-9]
    start, end = narrowing.min(), narrowing.max()
    after_start = plan.l_m > 5.0  # beyond the initial contraction from the packing density
    k = np.flatnonzero(after_start)[np.argmin(plan.density_per_m2[after_start])]
    assert start - 3.0 <= plan.l_m[k] <= end  # the minimum lies before the narrowest section
    assert plan.density_per_m2[k] <= 0.75 * plan.swarm.rho_d_per_m2  # and is clear
    assert plan.active['p7'].any()
    assert plan.density_per_m2[-1] == pytest.approx(plan.swarm.rho_d_per_m2, rel=1e-4)  # recovers


def test_speed_drops_where_the_curvature_limit_binds(shipped_plans: dict[str, Plan]) -> None:
    plan = shipped_plans['D']
    on_arcs = plan.active['p4']
    assert on_arcs.sum() > 50
    np.testing.assert_allclose(plan.speed_mps[on_arcs], plan.speed_limit_mps[on_arcs], rtol=1e-6)
    assert plan.speed_mps[on_arcs].max() < plan.swarm.v_max_mps - 0.5
    assert plan.speed_mps[-1] == pytest.approx(plan.swarm.v_max_mps)  # straight again at the end


def test_normal_narrowing_needs_no_pre_expansion(shipped_plans: dict[str, Plan]) -> None:
    for name in ('A', 'B'):
        plan = shipped_plans[name]
        later = plan.l_m > 5.0
        assert plan.density_per_m2[later].min() >= 0.99 * plan.swarm.rho_d_per_m2


# ---------------------------------------------------------------------- optimality


def test_convex_beats_polynomial_and_slsqp_on_scene_a(shipped_plans: dict[str, Plan]) -> None:
    scene = load_scene('A')
    convex = shipped_plans['A']  # plan_convex(scene A) as planned once for the module
    polynomial = plan_polynomial(scene.tube, scene.swarm, scene.planning)
    assert convex.objective['total'] <= polynomial.objective['total']
    v0, rho0 = initial_conditions(scene.swarm, scene.planning)
    _, _, _, j_slsqp = slsqp_plan(scene.tube, scene.swarm, scene.planning, 40, v0=v0, rho0=rho0)
    assert convex.objective['total'] <= j_slsqp
    # same grid, same formulation: the convex-concave procedure reaches SLSQP's optimum
    same = plan_convex(scene.tube, scene.swarm, replace(scene.planning, grid_step_m=scene.tube.length_m / 40))
    assert same.objective['total'] <= j_slsqp * (1 + 1e-6)


def test_rigid_shift_reading_plans_and_is_not_stricter_here() -> None:
    scene = load_scene('C')
    rigid = plan_convex(scene.tube, scene.swarm, replace(scene.planning, predictive_model='rigid_shift'))
    local = plan_convex(scene.tube, scene.swarm, scene.planning)
    assert rigid.certificate['p7'] <= 1e-3  # nodal, footprint frozen per iterate: small slack between nodes
    assert rigid.objective['total'] <= local.objective['total'] + 1e-9  # docs/theory.md §8.6: (b) barely binds
    with pytest.raises(PlanError, match='local-width reading of \\(p7\\) only'):
        plan_polynomial(scene.tube, scene.swarm, replace(scene.planning, predictive_model='rigid_shift'))


# ---------------------------------------------------------------------- infeasibility, before the solver


@pytest.fixture
def no_solver(monkeypatch):
    def forbidden(*args, **kwargs):
        pytest.fail('the solver ran although infeasibility was known beforehand')

    monkeypatch.setattr(ConvexPlanner, '__init__', forbidden)
    monkeypatch.setattr(planner_module.BandedPlanner, '__init__', forbidden)


@pytest.mark.parametrize(
    ('center', 'swarm', 'options', 'match'),
    [
        (
            ArcPath((ArcPiece(5.0), ArcPiece(6.0, radius_m=3.0), ArcPiece(5.0))),
            SwarmParams(),
            PlanningOptions(),
            r'\(p4\) is incompatible with \(p2\) at l = 4\.\d+ m.*below v_min = 2 m/s',
        ),
        (
            ArcPath((ArcPiece(20.0),)),
            SwarmParams(),
            PlanningOptions(rho0_per_m2=1.5),
            r'\(p5\) fails at l = 0: the initial density 1.5',
        ),
        (ArcPath((ArcPiece(20.0),)), SwarmParams(), PlanningOptions(v0_mps=6.0), r'\(p2\) fails at l = 0'),
        (
            ArcPath((ArcPiece(2.0), ArcPiece(10.0, radius_m=5.0))),
            SwarmParams(),
            PlanningOptions(v0_mps=5.0),
            r'\(p3\) and \(p4\) conflict at l = [01]\.\d+ m',
        ),
    ],
)
def test_infeasible_problems_fail_fast(center, swarm, options, match, no_solver) -> None:
    with pytest.raises(PlanError, match=match):
        plan_convex(tube_of(center, 1.0), swarm, options)


def test_impossible_pre_expansion_is_reported_with_its_arc_length(no_solver) -> None:
    # the tube narrows 8:1 right at the entrance: the density cannot fall from the packing value in time
    width = WidthProfile(
        4.0, (WidthPart('constant', 0.2), WidthPart('smooth', 0.3, to_m=0.5), WidthPart('constant', 9.5))
    )
    tube = VirtualTube(ArcPath((ArcPiece(10.0),)), width)
    with pytest.raises(PlanError, match=r'\(p7\) cannot hold at l = 0\.\d{3} m'):
        plan_convex(tube, SwarmParams(), PlanningOptions(lookahead_m=1.0))


def test_an_uncertified_plan_says_which_constraint_fails_where() -> None:
    """A certified straight-tube plan, then its speed raised 10 % above v_max at l = 20 m (where it rides v_max) and
    its initial density off by 5 %: (p2) by exactly 0.1 at 20 m, the rate (p3) on an interval next to it, the
    boundary values by 0.05."""
    tube, swarm, options = tube_of(ArcPath((ArcPiece(30.0),))), SwarmParams(), PlanningOptions(grid_step_m=0.5)
    plan = plan_convex(tube, swarm, options)
    assert plan.failures(tube) == ()
    speed, density = plan.speed_mps.copy(), plan.density_per_m2.copy()
    k = int(np.argmin(np.abs(plan.l_m - 20.0)))
    speed[k] = 1.1 * swarm.v_max_mps
    density[0] *= 1.05
    broken = make_plan(tube, swarm, options, plan.l_m, speed, density, solved=plan.solved, scene='line')
    places = worst_places(tube, swarm, options, plan.l_m, speed, density)
    assert places['p2'] == 20.0 and 19.5 <= places['p3'] < 20.0 and places['initial'] == 0.0
    assert math.isnan(places['p4'])  # a straight tube has no curvature limit to break
    failures = broken.failures(tube)
    assert failures[0] == '(p2) the speed band [v_min, v_max] is exceeded by 1.0e-01 (relative) at l = 20.000 m'
    assert failures[1].startswith('(p3) the speed change a_v is exceeded by ')
    assert failures[-1] == 'the initial speed and density miss the boundary values by 5.0e-02 (relative)'
    assert len(failures) == sum(value > CERTIFIED for value in broken.certificate.values())


# ---------------------------------------------------------------------- the Plan file


def test_plan_round_trips_through_its_file(tmp_path, shipped_plans: dict[str, Plan]) -> None:
    plan = shipped_plans['D']
    loaded = Plan.load(plan.save(tmp_path / 'sub' / 'plan.npz'), load_scene('D').tube)
    for name in ('l_m', 'speed_mps', 'density_per_m2', 'half_width_m', 'speed_limit_mps'):
        np.testing.assert_array_equal(getattr(loaded, name), getattr(plan, name))
    assert loaded.certificate == plan.certificate and loaded.objective == plan.objective
    assert loaded.swarm == plan.swarm and loaded.options == plan.options and loaded.scene == 'D'
    assert set(loaded.active) == set(plan.active)
    for key, mask in plan.active.items():
        np.testing.assert_array_equal(loaded.active[key], mask)
    l = np.linspace(-1.0, 61.0, 777)
    np.testing.assert_array_equal(loaded.speed(l), plan.speed(l))


def test_plan_interpolates_slowness_and_density_linearly(shipped_plans: dict[str, Plan]) -> None:
    plan = shipped_plans['A']
    mid = 0.5 * (plan.l_m[:-1] + plan.l_m[1:])
    np.testing.assert_allclose(1.0 / plan.speed(mid), 0.5 * (1 / plan.speed_mps[:-1] + 1 / plan.speed_mps[1:]))
    np.testing.assert_allclose(plan.density(mid), 0.5 * (plan.density_per_m2[:-1] + plan.density_per_m2[1:]))
    # the reported time is the integral of 1/v of the plan as used (independent quadrature)
    fine = np.linspace(0.0, plan.length_m, 200_001)
    assert plan.time_s == pytest.approx(np.trapezoid(1.0 / plan.speed(fine), fine), rel=1e-9)


def test_corrupt_plan_file_gives_plan_error(tmp_path) -> None:
    bad = tmp_path / 'bad.npz'
    bad.write_bytes(b'PK\x03\x04 not really a zip')
    with pytest.raises(PlanError, match='cannot read plan file .*bad.npz'):
        Plan.load(bad, load_scene('A').tube)


def test_weighting_density_makes_the_swarm_slow_down_where_p7_binds() -> None:
    scene = load_scene('C')
    faithful = plan_convex(scene.tube, scene.swarm, scene.planning)
    weighted = plan_convex(scene.tube, scene.swarm, replace(scene.planning, density_weight=100.0))
    near = (faithful.l_m > 12.0) & (faithful.l_m < 26.0)
    assert faithful.speed_mps[near].min() == pytest.approx(faithful.swarm.v_max_mps)  # mu = 1: density is cheap
    k = np.flatnonzero(near)[np.argmin(weighted.speed_mps[near])]
    assert weighted.speed_mps[k] < faithful.swarm.v_max_mps - 0.5  # mu = 100: time is traded for density
    assert np.abs(weighted.l_m[weighted.active['p7']] - weighted.l_m[k]).min() < 1.0  # where (p7) binds
    assert weighted.density_per_m2[near].min() > faithful.density_per_m2[near].min()
    assert weighted.is_certified(CERTIFIED)


def _tampered(tmp_path, plan: Plan, name: str, arrays: dict | None = None, meta: dict | None = None):
    from vtube_planning.npzfile import read_npz, write_npz

    stored, recorded = read_npz(plan.save(tmp_path / 'plan.npz'), PlanError, 'plan file')
    return write_npz(tmp_path / name, stored | (arrays or {}), recorded | (meta or {}))


def test_an_edited_plan_is_judged_by_what_it_holds_not_by_its_recorded_certificate(
    tmp_path, shipped_plans: dict[str, Plan]
) -> None:
    plan, tube = shipped_plans['D'], load_scene('D').tube
    fast = plan.speed_mps.copy()
    fast[5] = 50.0  # far above v_max; the recorded certificate still says every constraint holds
    perfect = {'certificate': dict.fromkeys(plan.certificate, 0.0)}
    loaded = Plan.load(_tampered(tmp_path, plan, 'fast.npz', {'speed_mps': fast}, perfect), tube)
    assert not loaded.is_certified() and loaded.certificate['p2'] > 1.0
    assert any(f.startswith('(p2) ') for f in loaded.failures(tube))
    assert loaded.time_s < plan.time_s  # the objective recomputed too


@pytest.mark.parametrize(
    ('arrays', 'meta', 'match'),
    [
        ({'speed_mps': 0.0}, None, 'holds no usable plan: a speed or a density is not > 0'),
        ({'density_per_m2': np.nan}, None, 'a grid point, speed or density is not a finite number'),
        ({'l_m': 2.0}, None, "its grid does not rise from 0 to the tube's length"),
        (None, {'provenance': [1, 2]}, 'its scene must be a name and its provenance a table'),
        (None, {'tube_hash': 'feed'}, "made for scene 'D'\\) does not fit this tube"),
    ],
)
def test_a_plan_with_unusable_numbers_is_refused(tmp_path, shipped_plans, arrays, meta, match) -> None:
    plan = shipped_plans['D']
    edited = {}
    for name, value in (arrays or {}).items():
        values = getattr(plan, name).copy()
        values[3] = value
        edited[name] = values
    with pytest.raises(PlanError, match=match):
        Plan.load(_tampered(tmp_path, plan, 'bad.npz', edited, meta), load_scene('D').tube)


# ---------------------------------------------------------------------- the relaxed plan (freedom = 'relaxed')


@pytest.mark.parametrize('radius_m', [4.0, 9.0])
def test_a_relaxed_plan_starts_at_v_max_and_ignores_p3_and_p4(radius_m: float) -> None:
    """In a circle whose (p4) holds the paper's plan at sqrt(a_n r) after a ramp from v_min, the relaxed plan flies
    v_max from l = 0: the freedom of the unplanned swarm in the paper's robot model."""
    swarm = SwarmParams()
    tube = tube_of(ArcPath((ArcPiece(radius_m * 2.5, radius_m=radius_m),)), 0.5 * radius_m)
    paper = plan_convex(tube, swarm, PlanningOptions(grid_step_m=0.1))
    relaxed = plan_convex(tube, swarm, PlanningOptions(grid_step_m=0.1, freedom='relaxed'))
    assert paper.speed_mps.max() == pytest.approx(math.sqrt(swarm.a_n_mps2 * radius_m), rel=1e-7)
    np.testing.assert_allclose(relaxed.speed_mps, swarm.v_max_mps, rtol=1e-7)
    assert relaxed.time_s == pytest.approx(tube.length_m / swarm.v_max_mps, rel=1e-7)
    assert relaxed.is_certified(CERTIFIED)  # held to what it was planned under
    assert initial_conditions(swarm, relaxed.options)[0] == swarm.v_max_mps
    assert np.all(relaxed.speed_limit_mps > swarm.v_max_mps)  # the plan file's speed limit is the relaxed one


def test_a_relaxed_plan_keeps_the_other_constraints_and_a_given_start() -> None:
    """(p2), (p5)-(p7) still hold: the density falls at the (p6) limit as on a straight tube, and v0_mps given is
    the start; the paper's certificate of that plan fails (p3) or (p4), the relaxed one does not."""
    swarm = SwarmParams()
    scene = load_scene('D')
    options = replace(scene.planning, freedom='relaxed', v0_mps=3.0)
    plan = plan_convex(scene.tube, swarm, options)
    assert plan.speed_mps[0] == pytest.approx(3.0) and plan.speed_mps[5] == pytest.approx(swarm.v_max_mps)
    assert plan.is_certified(CERTIFIED) and plan.certificate['p7'] <= CERTIFIED
    as_paper = make_plan(
        scene.tube,
        swarm,
        replace(options, freedom='paper'),
        plan.l_m,
        plan.speed_mps,
        plan.density_per_m2,
        solved=plan.solved,
        scene='D',
    )
    assert max(as_paper.certificate['p3'], as_paper.certificate['p4']) > 0.1
    with pytest.raises(ValueError, match='freedom must be one of'):
        PlanningOptions(freedom='free')


def test_the_paper_plan_is_unchanged_by_the_new_options(shipped_plans: dict[str, Plan]) -> None:
    """freedom = 'paper' and braking_room = False are the defaults: the same plan, bit for bit."""
    scene = load_scene('C')
    again = plan_convex(scene.tube, scene.swarm, replace(scene.planning, freedom='paper', braking_room=False))
    assert np.array_equal(again.speed_mps, shipped_plans['C'].speed_mps)
    assert np.array_equal(again.density_per_m2, shipped_plans['C'].density_per_m2)
    assert 'braking' not in again.certificate
