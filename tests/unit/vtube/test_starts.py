"""Where a simulated swarm starts: the grid of a paper scene, a Robotarium scene's entry formation, the given
positions (a start with a body on an obstacle: tests/unit/vtube_planning/swarm/test_map_contact.py)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from robotarium_exp.experiment import initial_conditions
from robotarium_exp.scene import load_scene
from vtube.starts import GRID_START, ROBOTARIUM_START, require_room_beyond_goal, robotarium_start, started
from vtube_planning.swarm.formation import as_positions
from vtube_planning.swarm.simulate import SimConfig


def test_a_paper_scene_starts_on_the_simulator_s_grid() -> None:
    scene = load_scene('C')
    assert robotarium_start(scene, scene.swarm) is None
    config, said = started(scene, scene.swarm, SimConfig(seed=2))
    assert (config, said) == (SimConfig(seed=2), GRID_START)


def test_a_robotarium_scene_starts_where_its_flight_does() -> None:
    scene = load_scene('robotarium_curve')
    swarm = replace(scene.swarm, n_robots=4)
    expected = initial_conditions(replace(scene, swarm=swarm))[:2]
    np.testing.assert_array_equal(robotarium_start(scene, swarm), expected)
    config, said = started(scene, swarm, SimConfig())
    assert said == ROBOTARIUM_START and config.initial_positions_m == as_positions(expected)


def test_given_positions_are_kept_and_said() -> None:
    scene = load_scene('C')
    swarm = replace(scene.swarm, n_robots=2)
    given = SimConfig(initial_positions_m=[[-3.0, -3.0], [-1.0, 1.0]])
    config, said = started(scene, swarm, given)
    assert config == given and said == 'the given positions'


def test_a_goal_without_room_to_run_out_is_refused_naming_the_map_file_s_keys() -> None:
    """Issue 49, item 7: the paper's model drives each robot on beyond the goal until the last one is through; a
    generated scene whose straight run-out (at least the start formation's depth) leaves the map or meets an
    obstacle is refused. Scene A runs straight along x to (L, 0)."""
    import pytest

    from vtube_planning.errors import SceneError
    from vtube_planning.geometry.obstacles import Disc, Obstacles
    from vtube_planning.geometry.workspace import Workspace

    scene = load_scene('A')
    end = scene.tube.length_m
    roomy = replace(scene, workspace=Workspace(-40.0, end + 30.0, -20.0, 20.0))
    require_room_beyond_goal(roomy, 'map.toml')  # 30 m ahead: nothing raised
    short = replace(roomy, workspace=Workspace(-40.0, end + 5.0, -20.0, 20.0))
    with pytest.raises(SceneError, match=r'the run-out beyond the goal puts \d+ robot bodies outside the workspace'):
        require_room_beyond_goal(short, 'map.toml')
    walled = replace(roomy, obstacles=Obstacles(discs=(Disc((end + 6.0, 0.0), 0.5),)))
    with pytest.raises(SceneError, match=r'on an obstacle, .*in map.toml, move goal_m \(or goal_region_m\) of '):
        require_room_beyond_goal(walled, 'map.toml')
    beside = replace(roomy, obstacles=Obstacles(discs=(Disc((end + 6.0, scene.tube.half_width(end) + 1.0), 0.5),)))
    require_room_beyond_goal(beside, 'map.toml')  # beside the straight run-out, clear of its bodies: nothing raised
