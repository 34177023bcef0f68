"""Replanning from a measured state: the optimal tail of a plan, clipping, refusals, and replanning in flight."""

from __future__ import annotations

from dataclasses import asdict

import numpy as np
import pytest

from vtube_planning.errors import ParamsError, PlanError
from vtube_planning.geometry.scene import load_scene
from vtube_planning.planning.constraints import objective_terms
from vtube_planning.planning.plan import Plan, SwarmState
from vtube_planning.planning.planner import plan_convex, replan
from vtube_planning.swarm.faults import RobotFailure
from vtube_planning.swarm.replanner import Replanner
from vtube_planning.swarm.simulate import SimConfig, simulate


@pytest.fixture(scope='module')
def scene_c():
    scene = load_scene('C')
    return scene, plan_convex(scene.tube, scene.swarm, scene.planning, scene='C')


def state_of(plan: Plan, k: int, n_robots: int | None = None) -> SwarmState:
    return SwarmState(float(plan.l_m[k]), float(plan.speed_mps[k]), float(plan.density_per_m2[k]), n_robots)


def test_replanning_from_the_entrance_in_the_plans_own_state_gives_the_plan(scene_c) -> None:
    scene, plan = scene_c
    again = replan(plan, state_of(plan, 0), scene.tube)
    np.testing.assert_array_equal(again.l_m, plan.l_m)
    assert again.objective['total'] == pytest.approx(plan.objective['total'], rel=1e-12)
    np.testing.assert_allclose(again.speed_mps, plan.speed_mps, rtol=1e-9)


@pytest.mark.parametrize('k', [40, 90, 150, 220])
def test_replanning_from_a_point_of_an_optimal_plan_gives_its_tail(scene_c, k: int) -> None:
    # every constraint is local in l and (p1) adds up over the grid: the tail of an optimal plan is optimal for the
    # rest of the tube from the state it reaches there (Bellman), on the same grid points
    scene, plan = scene_c
    rest = replan(plan, state_of(plan, k), scene.tube)
    np.testing.assert_allclose(rest.l_m, plan.l_m[k:], atol=1e-9)
    tail = objective_terms(plan.l_m[k:], plan.speed_mps[k:], plan.density_per_m2[k:], plan.swarm, plan.options)
    assert rest.objective['total'] == pytest.approx(tail['total'], rel=1e-8)
    np.testing.assert_allclose(rest.speed_mps, plan.speed_mps[k:], rtol=1e-5)
    assert rest.max_violation <= 1e-8 and rest.solved.formulation == 'banded'


def test_a_measured_state_outside_the_constraints_is_clipped_into_them(scene_c) -> None:
    scene, plan = scene_c
    rest = replan(plan, SwarmState(5.0, 9.0, 3.0), scene.tube)
    swarm = plan.swarm
    assert rest.speed_mps[0] == pytest.approx(swarm.v_max_mps) and rest.density_per_m2[0] == swarm.rho_max_per_m2
    assert asdict(rest.solved.replanned_from.measured) == {
        'arc_length_m': 5.0,
        'speed_mps': 9.0,
        'density_per_m2': 3.0,
        'n_robots': None,
    }
    assert rest.max_violation <= 1e-8
    slow = replan(plan, SwarmState(5.0, 0.1, 0.2), scene.tube)
    assert slow.speed_mps[0] == pytest.approx(swarm.v_min_mps)


def test_replanning_for_the_robots_still_flying_plans_for_that_swarm(scene_c) -> None:
    scene, plan = scene_c
    rest = replan(plan, state_of(plan, 60, n_robots=19), scene.tube)
    assert rest.swarm.n_robots == 19 and rest.max_violation <= 1e-8
    assert rest.swarm.a_rho != plan.swarm.a_rho  # (p8) depends on N


@pytest.mark.parametrize('start', [-1.0, 59.6, float('nan')])
def test_replanning_needs_two_grid_steps_of_tube_left(scene_c, start: float) -> None:
    scene, plan = scene_c
    with pytest.raises(PlanError, match='must hold at least two grid steps'):
        replan(plan, SwarmState(start, 3.0, 0.2), scene.tube)


def test_a_swarm_too_fast_to_brake_for_a_turn_is_told_where() -> None:
    scene = load_scene('D')
    plan = plan_convex(scene.tube, scene.swarm, scene.planning)
    turn = float(scene.tube.center.breakpoints[1])
    with pytest.raises(PlanError, match=r'\(p3\) and \(p4\) conflict at l = '):
        replan(plan, SwarmState(turn - 0.5, scene.swarm.v_max_mps, 0.2), scene.tube)


def test_a_replan_for_another_tube_is_refused(scene_c) -> None:
    _, plan = scene_c
    with pytest.raises(PlanError, match='a different tube'):
        replan(plan, state_of(plan, 10), load_scene('A').tube)


# ---------------------------------------------------------------------- in flight


@pytest.fixture(scope='module')
def replanned_flight(scene_c):
    scene, plan = scene_c
    config = SimConfig(seed=1, replan_every_s=0.5, failure=RobotFailure(robot=3, at_m=20.0))
    return simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=config)


def test_the_flight_replans_every_period_from_its_measured_state(scene_c, replanned_flight) -> None:
    scene, _ = scene_c
    result = replanned_flight
    calls = result.meta['replans']
    steps = [c['step'] for c in calls]
    assert steps and all(step % 25 == 0 for step in steps) and steps == sorted(set(steps))
    assert all(c['wall_ms'] > 0 for c in calls)
    done = [c for c in calls if not c['error']]
    assert len(done) >= 10
    # each replan starts where the working robots were on average (robot 3 failed at l = 20 m)
    for call in done:
        l_now = result.l_m[call['step']]
        working = np.ones(l_now.size, dtype=bool)
        if (result.l_m[: call['step'], 3] >= 20.0).any():  # failed at an earlier step
            working[3] = False
        flying = working & (l_now < scene.tube.length_m)
        assert call['from_m'] == pytest.approx(max(0.0, l_now[flying].mean()), abs=0.1)  # true vs seen: same here
    assert [c['from_m'] for c in done] == sorted(c['from_m'] for c in done)


def test_the_plan_as_flown_is_each_replan_from_where_it_starts(scene_c) -> None:
    scene, plan = scene_c
    replanner = Replanner(plan, scene.tube, every=25)
    first = replan(plan, state_of(plan, 40), scene.tube)
    second = replan(plan, SwarmState(30.0, 4.0, 0.15), scene.tube)
    replanner.profiles += [first.profile, second.profile]
    flown = replanner.flown()
    # between the last kept grid point of one profile (29.75 m) and the next profile's start the two are joined linearly
    before, middle, after = np.linspace(0, 9.9, 50), np.linspace(10.0, 29.75, 50), np.linspace(30.0, 60.0, 50)
    np.testing.assert_allclose(flown.speed(before), plan.speed(before), rtol=1e-12)
    np.testing.assert_allclose(flown.density(middle), first.density(middle), rtol=1e-12)
    np.testing.assert_allclose(flown.speed(after), second.speed(after), rtol=1e-12)


def test_replanning_needs_a_plan_and_a_period_of_at_least_zero(scene_c) -> None:
    scene, _ = scene_c
    with pytest.raises(ParamsError, match='replan_every_s must be a finite number >= 0'):
        SimConfig(replan_every_s=-0.5)
    with pytest.raises(ParamsError, match='replanning \\(replan_every_s\\) needs a plan'):
        simulate(scene.tube, scene.swarm, scene.control, plan=None, config=SimConfig(replan_every_s=0.5))
