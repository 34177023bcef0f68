"""Where a simulated swarm starts: the grid of a paper scene, a Robotarium scene's entry formation, the given
positions (a start with a body on an obstacle: tests/unit/vtube_planning/swarm/test_map_contact.py)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from robotarium_exp.experiment import initial_conditions
from robotarium_exp.scene import load_scene
from vtube.starts import GRID_START, ROBOTARIUM_START, robotarium_start, started
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
