"""The fastest admissible start: admissible, none faster, and the same plan in fewer iterations."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from vtube_planning.geometry.scene import list_scenes, load_scene
from vtube_planning.planning.constraints import certify
from vtube_planning.planning.fastest_start import fastest_admissible
from vtube_planning.planning.planner import plan_convex
from vtube_planning.planning.problem import discretise

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
