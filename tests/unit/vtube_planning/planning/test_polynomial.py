"""The polynomial planner: C^1 cubic segments whose objective matches the sampled one."""

from __future__ import annotations

from vtube_planning.geometry.scene import load_scene
from vtube_planning.planning.polynomial import plan_polynomial

CERTIFIED = 1e-6  # the bound on relative violations


def test_polynomial_plan_is_c1_cubic_segments() -> None:
    scene = load_scene('B')
    plan = plan_polynomial(scene.tube, scene.swarm, scene.planning)
    fit = plan.solved.polynomial
    assert plan.solved.status == 'converged' and fit is not None and fit.p3_slack < 1e-8
    assert abs(fit.objective - plan.objective['total']) < 1e-3  # sampled vs exact
    assert plan.certificate['p2'] <= CERTIFIED and plan.certificate['p4'] <= CERTIFIED  # control-point bounds
