"""The discretised problem: refined grids against the continuous optimum and the reference solver."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from tests.support.plans import CERTIFICATE, assert_same_plan
from vtube_planning.errors import ParamsError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.scene import load_scene
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.params import PlanningOptions, SwarmParams
from vtube_planning.planning.planner import plan_convex
from vtube_planning.planning.problem import refined_grid, uniform_grid

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
