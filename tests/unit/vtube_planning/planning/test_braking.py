"""Room for braking: h(rho) against the spacing it stands for, its tangents above it, and plans that keep it."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from vtube_planning.errors import PlanError
from vtube_planning.geometry.scene import load_scene
from vtube_planning.params import SwarmParams
from vtube_planning.planning.braking import braking_excess, braking_slowness, braking_tangent, densest_braking
from vtube_planning.planning.planner import plan_convex

SWARM = SwarmParams()


def test_h_is_the_speed_whose_braking_fills_the_spacing() -> None:
    """At w = h(rho) the spacing 1 / sqrt(rho) is exactly 2 r_s plus the braking distance from 1 / w to v_min."""
    rho = np.linspace(0.005, densest_braking(SWARM), 50)
    v = 1.0 / braking_slowness(SWARM, rho)
    braking = (v**2 - SWARM.v_min_mps**2) / (2.0 * SWARM.a_v_mps2)
    np.testing.assert_allclose(1.0 / np.sqrt(rho), 2.0 * SWARM.r_s_m + braking, rtol=1e-12)
    assert v[-1] == pytest.approx(SWARM.v_min_mps)  # no room left beyond 2 r_s: only v_min
    pairs = braking_excess(SWARM, np.repeat(v, 2), np.repeat(rho, 2))[::2]  # intervals of constant v and rho
    np.testing.assert_allclose(pairs, 0.0, atol=1e-12)


def test_every_tangent_lies_above_h() -> None:
    """h is concave: its tangent at any point bounds it from above everywhere, and touches it there."""
    rng = np.random.default_rng(3)
    rho = rng.uniform(1e-3, densest_braking(SWARM), 400)
    at = rng.uniform(1e-3, densest_braking(SWARM), 400)
    slope, intercept = braking_tangent(SWARM, at)
    assert np.all(slope * rho + intercept >= braking_slowness(SWARM, rho) - 1e-14)
    np.testing.assert_allclose(slope * at + intercept, braking_slowness(SWARM, at), rtol=1e-12)
    step = 1e-7
    numeric = (braking_slowness(SWARM, at + step) - braking_slowness(SWARM, at - step)) / (2 * step)
    np.testing.assert_allclose(slope, numeric, rtol=1e-5)


@pytest.mark.parametrize('name', ['C', 'D'])
def test_a_plan_with_room_for_braking_keeps_it_everywhere(name: str) -> None:
    """Certified with the entry 'braking', checked again here on the plan's own samples; the banded and cvxpy
    solvers reach the same plan."""
    scene = load_scene(name)
    options = replace(scene.planning, braking_room=True)
    plan = plan_convex(scene.tube, scene.swarm, options)
    assert plan.is_certified(1e-6) and 'braking' in plan.certificate
    assert np.all(braking_excess(scene.swarm, plan.speed_mps, plan.density_per_m2) <= 1e-8)
    reference = plan_convex(scene.tube, scene.swarm, options, formulation='cvxpy')
    assert plan.objective['total'] == pytest.approx(reference.objective['total'], rel=1e-7)
    paper = plan_convex(scene.tube, scene.swarm, scene.planning)
    assert np.max(braking_excess(scene.swarm, paper.speed_mps, paper.density_per_m2)) > 1.0  # the paper's does not


def test_a_start_that_cannot_brake_is_refused_with_its_place() -> None:
    scene = load_scene('C')
    options = replace(scene.planning, braking_room=True, v0_mps=5.0)
    with pytest.raises(PlanError, match=r'the room for braking cannot hold at l = 0\.000 m'):
        plan_convex(scene.tube, scene.swarm, options)
