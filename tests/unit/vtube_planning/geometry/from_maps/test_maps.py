"""The seeded map families: the same seed gives the same map, the ends stay clear, the bottleneck has the width
asked for, and each family gives certified tubes (checked at 1 cm) as well as refusals over a few seeds."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from tests.unit.vtube_planning.geometry.from_maps.test_generate import assert_misses
from vtube_planning.geometry.from_maps.generate import TubeGenerationError, generate_tube
from vtube_planning.geometry.from_maps.maps import CLEAR_OF_ENDS_M, FAMILIES, GOAL_M, START_M, random_map


@pytest.mark.parametrize('family', FAMILIES)
def test_a_family_is_seeded_and_keeps_the_ends_clear(family: str) -> None:
    a, b, c = random_map(family, 7), random_map(family, 7), random_map(family, 8)
    assert a == b and a.obstacles != c.obstacles
    ends = np.array([START_M, GOAL_M])
    assert a.obstacles.clearance(ends).min() >= min(CLEAR_OF_ENDS_M, 2.0 - 1e-9)  # the wall ends 2 m in at most
    assert a.start_m == START_M and a.goal_m == GOAL_M and a.half_width_min_m == 1.2


def test_the_bottleneck_opening_has_the_width_asked_for() -> None:
    spec = random_map('bottleneck', 3, clutter=0, width_m=3.5)
    low, high = spec.obstacles.polygons
    assert max(y for _, y in high.vertices_m) == 40.0 and min(y for _, y in low.vertices_m) == 0.0
    gap = min(y for _, y in high.vertices_m) - max(y for _, y in low.vertices_m)
    assert gap == pytest.approx(3.5)
    made = generate_tube(spec)  # no clutter: the only way is through the opening
    x_wall = low.vertices_m[0][0] + 1.0
    l_at = made.tube.project(np.array([[x_wall], [max(y for _, y in low.vertices_m) + 1.75]])).l_m[0]
    assert math.isfinite(l_at)
    assert_misses(made.tube, spec.obstacles, 0.3)


def test_an_unknown_family_is_named() -> None:
    with pytest.raises(
        ValueError, match=r"unknown map family 'maze'; choose one of \('forest', 'blocks', 'bottleneck'\)"
    ):
        random_map('maze', 0)


def test_blocks_give_certified_tubes_and_refusals_with_reasons() -> None:
    outcomes = []
    for seed in range(4):
        spec = random_map('blocks', seed)
        try:
            made = generate_tube(spec)
        except TubeGenerationError as err:
            outcomes.append(str(err).split(':')[0])
            continue
        assert_misses(made.tube, spec.obstacles, 0.3, step_m=0.1, across=11)  # 1 cm: the benchmark's
        outcomes.append('certified')
    assert 'certified' in outcomes and any(o != 'certified' for o in outcomes), outcomes


def test_a_difficulty_out_of_range_is_named() -> None:
    with pytest.raises(ValueError, match=r'opening width_m in \[1, 20\] m; got seed 0, clutter 30, width_m 25'):
        random_map('bottleneck', 0, width_m=25.0)
    with pytest.raises(ValueError, match='clutter >= 0'):
        random_map('forest', 0, clutter=-1)


def test_a_scene_on_a_map_flies_the_maps_tube_with_its_own_swarm() -> None:
    from vtube_planning.errors import ParamsError
    from vtube_planning.geometry.from_maps.maps import scene_on_map
    from vtube_planning.geometry.scene import load_scene

    scene = load_scene('C')
    spec = random_map('bottleneck', 0, width_m=5.0)
    on = scene_on_map(scene, 'bottleneck', 0, width_m=5.0)
    fresh = generate_tube(spec).tube
    assert on.tube.center.pieces == fresh.center.pieces and on.tube.width.parts == fresh.width.parts
    assert on.obstacles == spec.obstacles and on.swarm == scene.swarm and on.control == scene.control
    assert on.source != scene.source != scene_on_map(scene, 'bottleneck', 1, width_m=5.0).source  # plans cached apart
    with pytest.raises(ParamsError, match='declared for the robotarium; the random maps are 80 m x 40 m'):
        scene_on_map(replace(scene, testbed='robotarium'), 'bottleneck', 0)
