"""Bodies on obstacles and outside the workspace, over a run and at its start (issue 49: simulations on map scenes
started outside the map's walls and flew through them, and the summary said nothing)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from vtube_planning.errors import SceneError
from vtube_planning.geometry.obstacles import Disc, Obstacles
from vtube_planning.geometry.scene import load_scene
from vtube_planning.geometry.workspace import Workspace
from vtube_planning.swarm.map_contact import MapContact, fails_beyond_exit, map_contact, require_clear_start


def scene_with_a_map():
    """Scene A (a tube from (0, 0) along x) on a map [-5, 200] x [-20, 20] with a disc of radius 1 at (-3, 10)."""
    scene = load_scene('A')
    return replace(
        scene, workspace=Workspace(-5.0, 200.0, -20.0, 20.0), obstacles=Obstacles(discs=(Disc((-3.0, 10.0), 1.0),))
    )


def test_contacts_are_counted_per_robot_step_with_the_first_time_and_place() -> None:
    scene = scene_with_a_map()
    t = np.arange(4) * 0.5
    positions = np.zeros((4, 2, 2))
    positions[:, :, 0] = [[-3.0, 8.7], [-3.0, 8.5], [0.0, 0.0], [-4.8, 0.0]]  # 0.3 from the disc, then 0.5
    positions[:, :, 1] = [[10.0, 0.0], [10.0, 19.9], [10.0, 0.0], [10.0, 0.0]]  # once 0.1 from the edge
    contact = map_contact(t, positions, scene, body_radius_m=0.4)
    assert contact == MapContact(1, 2, (0.0, -3.0, 8.7), (0.5, 10.0, 19.9))  # (-4.8, 0): 0.2 from the edge
    assert contact.failures() == (
        'robot bodies were on an obstacle in 1 robot-steps (first at t = 0.00 s, (-3.00, 8.70))',
        'robot bodies were outside the workspace (the map) in 2 robot-steps (first at t = 0.50 s, (10.00, 19.90))',
    )
    assert map_contact(t, positions, load_scene('A'), 0.4) == MapContact(0, 0)  # no map: nothing to touch


def test_beyond_the_exit_the_workspace_is_counted_apart() -> None:
    scene = scene_with_a_map()
    beyond = scene.tube.length_m + 1.0
    positions = np.zeros((3, 2, 1))
    positions[:, 1, 0] = [0.0, 19.9, 19.9]  # over the edge twice, the second time past the exit
    l_m = np.array([[1.0], [2.0], [beyond]])
    contact = map_contact(np.arange(3.0), positions, scene, 0.3, l_m)
    assert (contact.outside_workspace, contact.outside_after_exit) == (1, 1)
    back = np.array([[1.0], [beyond], [2.0]])  # once past the exit, a robot stays passed
    assert map_contact(np.arange(3.0), positions, scene, 0.3, back).outside_after_exit == 2


def test_beyond_the_exit_obstacles_fail_the_run_too_counted_apart_with_their_fix() -> None:
    """Issue 49, item 7: bodies on obstacles or off the map over the *whole* run fail it. A robot past the exit
    drives on (the paper's model does not park): a wall beyond the goal it drives into fails the run, counted and
    said apart, naming the map file's keys that give it room."""
    scene = replace(scene_with_a_map(), obstacles=Obstacles(discs=(Disc((150.0, 0.0), 1.0),)))
    beyond = scene.tube.length_m + 1.0
    positions = np.zeros((3, 2, 1))
    positions[:, 0, 0] = [150.0, 150.0, 150.0]  # on the disc throughout
    l_m = np.array([[1.0], [beyond], [beyond + 1.0]])
    contact = map_contact(np.arange(3.0), positions, scene, 0.3, l_m)
    assert (contact.on_obstacles, contact.on_obstacles_after_exit) == (1, 2)
    assert contact.first_on_obstacle_after_exit == (1.0, 150.0, 0.0)
    before, after = contact.failures()
    assert before == 'robot bodies were on an obstacle in 1 robot-steps (first at t = 0.00 s, (150.00, 0.00))'
    assert after.startswith(
        'robot bodies were on an obstacle in 2 robot-steps beyond the exit (first at t = 1.00 s, (150.00, 0.00)): '
        'the robots drive on beyond the goal'
    )
    assert all(key in after for key in ('goal_m', 'goal_region_m', 'goal_heading_deg', 'lead_m', '[tube.generate]'))
    only_after = map_contact(np.arange(3.0), positions, scene, 0.3, l_m + beyond)
    assert [f.split(' (first')[0] for f in only_after.failures()] == [
        'robot bodies were on an obstacle in 3 robot-steps beyond the exit'
    ]
    off_too = replace(scene, workspace=Workspace(-5.0, 149.0, -20.0, 20.0))  # the disc's centre is off the map too
    both = map_contact(np.arange(3.0), positions, off_too, 0.3, l_m + beyond).failures()
    assert [f.split(' (first')[0] for f in both] == [
        'robot bodies were on an obstacle in 3 robot-steps beyond the exit',
        'robot bodies were outside the workspace (the map) in 3 robot-steps beyond the exit',
    ]
    assert 'goal_m' not in both[0] and 'goal_m' in both[1]  # the fix once, after the last


def test_a_simulation_of_a_robotarium_scene_is_not_failed_beyond_the_exit_where_its_flight_parks() -> None:
    """The one exception: the paper's model, simulated, drives a Robotarium scene's robots on where the flight parks
    them (and `robotarium run` judges that); a recorded flight, which parks, is failed there."""
    scene = replace(scene_with_a_map(), testbed='robotarium')
    positions = np.zeros((2, 2, 1))
    positions[:, 1, 0] = 19.9  # over the edge, past the exit
    l_m = np.full((2, 1), scene.tube.length_m + 1.0)
    simulated = map_contact(np.arange(2.0), positions, scene, 0.3, l_m)
    assert simulated.outside_after_exit == 2 and simulated.failures() == ()
    assert fails_beyond_exit(scene, parks=True) and not fails_beyond_exit(scene, parks=False)
    assert fails_beyond_exit(scene_with_a_map(), parks=False)
    flown = map_contact(np.arange(2.0), positions, scene, 0.3, l_m, parks=True)
    assert (
        len(flown.failures()) == 1 and 'outside the workspace (the map) in 2 robot-steps beyond' in flown.failures()[0]
    )


def test_a_start_on_the_map_s_edge_or_an_obstacle_is_refused() -> None:
    scene = scene_with_a_map()
    require_clear_start(np.array([[-1.0, -2.0], [0.0, 1.0]]), scene, 0.3, 'fix it.')  # clear: nothing raised
    with pytest.raises(SceneError, match=r'the start puts 1 robot bodies outside the workspace \(the map\), the first'):
        require_clear_start(np.array([[-4.9, -2.0], [0.0, 1.0]]), scene, 0.3, 'fix it.')
    with pytest.raises(SceneError, match=r'on an obstacle, the first at \(-3.00, 9.20\); fix it\.'):
        require_clear_start(np.array([[-3.0], [9.2]]), scene, 0.3, 'fix it.')
