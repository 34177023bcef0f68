"""Where a simulated swarm starts: the given positions, a Robotarium scene's entry formation (as its flight starts),
or the simulator's grid; refused where a body would start on an obstacle or off the map. A map file's generated
scene is checked for room at both ends: to start, and to run out beyond the goal."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from robotarium_exp.experiment import initial_conditions
from vtube_planning.geometry.scene import Scene
from vtube_planning.params import SwarmParams
from vtube_planning.swarm.formation import FloatArray, as_positions, initial_formation, start_formation
from vtube_planning.swarm.map_contact import require_clear_start
from vtube_planning.swarm.simulate import SimConfig

__all__ = [
    'GRID_START',
    'ROBOTARIUM_START',
    'START_FIX',
    'require_room_beyond_goal',
    'require_room_to_start',
    'robotarium_start',
    'started',
]


def robotarium_start(scene: Scene, swarm: SwarmParams) -> FloatArray | None:
    """Where the robots of a Robotarium scene (one with a ``[robotarium]`` table) start on the testbed, (2, N): the
    centres of its start formation for ``swarm``'s robots; None for another scene (the simulator's grid): the hook
    through which a simulation of a Robotarium scene starts as its flight does."""
    if scene.testbed != 'robotarium':
        return None
    start: FloatArray = initial_conditions(replace(scene, swarm=swarm))[:2]
    return start


GRID_START = 'a grid before the entrance (spacing 2 r_a)'
ROBOTARIUM_START = "the Robotarium flight's entry formation (its robots' centres)"
START_FIX = (
    'give the tube room before its entrance (a map file: move start_m inwards or lengthen lead_m), or fewer robots.'
)


def started(scene: Scene, swarm: SwarmParams, config: SimConfig) -> tuple[SimConfig, str]:
    """``config`` with where the robots start (the given positions, a Robotarium scene's entry formation, else the
    simulator's grid), and that place in words; refused where a body would start on an obstacle or off the map."""
    robotarium = None if config.initial_positions_m is not None else robotarium_start(scene, swarm)
    if robotarium is not None:
        config = replace(config, initial_positions_m=as_positions(robotarium))
    start = start_formation(scene.tube, swarm, config.initial_positions_m, config.seed, config.jitter_m)
    require_clear_start(start, scene, swarm.r_p_m, START_FIX)
    given = 'the given positions' if robotarium is None else ROBOTARIUM_START
    return config, GRID_START if config.initial_positions_m is None else given


def _formation(scene: Scene) -> tuple[FloatArray, float, float]:
    """The start formation of ``scene``'s swarm (2, N), the body radius its start is checked with, and its depth
    along the tube: the Robotarium's entry formation (bodies r_p), else the simulator's grid before the entrance,
    unjittered, each body r_p and three standard deviations of the simulator's default jitter (so that a simulation's
    start, checked again with its own jitter, finds room at any seed but in the rarest)."""
    swarm = scene.swarm
    robotarium = robotarium_start(scene, swarm)
    if robotarium is not None:
        positions, radius = robotarium, swarm.r_p_m
    else:
        positions = initial_formation(scene.tube, swarm, np.random.default_rng(0), 0.0)
        radius = swarm.r_p_m + 3.0 * SimConfig().jitter_m
    depth = float(np.ptp(scene.tube.project(positions).l_m)) + 2.0 * swarm.r_a_m
    return positions, radius, depth


def _heading_deg(scene: Scene, l_m: float) -> float:
    """The tube's heading at arc length ``l_m``, in degrees."""
    return math.degrees(math.atan2(*scene.tube.tangent(l_m)[::-1]))


def require_room_to_start(scene: Scene, map_file: str) -> None:
    """Refuse a scene generated from ``map_file`` whose swarm could not start in free space inside the map
    (`_formation`)."""
    swarm = scene.swarm
    positions, radius, depth = _formation(scene)
    fix = (
        f'the {swarm.n_robots} robots start in a formation {depth:.1f} m deep before the entrance, behind start_m along '
        f"the tube's first heading ({_heading_deg(scene, 0.0):.0f} degrees): in {map_file}, move start_m (or "
        'start_region_m) of [tube.generate] to where that much room lies behind it, or give start_heading_deg pointing '
        'away from the obstacle with lead_m, or fewer robots ([swarm] n_robots); nothing was written.'
    )
    require_clear_start(positions, scene, radius, fix)


def require_room_beyond_goal(scene: Scene, map_file: str) -> None:
    """Refuse a scene generated from ``map_file`` whose robots could not run out beyond the goal in free space inside
    the map: the paper's model drives each robot on past the exit until the last one is through, along the tube's
    straight continuation, at least as far as the start formation is deep (farther where the swarm leaves long: a
    simulation tells). Every body r_p, its centre across the exit's half-width less r_p, r_p apart along and across.
    A Robotarium scene is not checked here: its flight parks, and its parking slots are checked with the flight."""
    swarm = scene.swarm
    if robotarium_start(scene, swarm) is not None:
        return
    tube, radius = scene.tube, swarm.r_p_m
    _, _, depth = _formation(scene)
    exit_l = tube.length_m
    half = max(float(tube.half_width(exit_l)) - radius, 0.0)
    along, across = np.meshgrid(
        np.linspace(0.0, depth, math.ceil(depth / radius) + 1),
        np.linspace(-half, half, math.ceil(2.0 * half / radius) + 1),
    )
    points = (
        tube.center_at(exit_l)[:, None]
        + tube.tangent(exit_l)[:, None] * along.ravel()
        + tube.normal(exit_l)[:, None] * across.ravel()
    )
    fix = (
        f'the robots drive on beyond the goal until the last one is through, at least {depth:.1f} m (the depth of the '
        f"{swarm.n_robots} robots' start formation) along the tube's last heading ({_heading_deg(scene, exit_l):.0f} "
        f'degrees): in {map_file}, move goal_m (or goal_region_m) of [tube.generate] to where that much room lies '
        'ahead of it, or give goal_heading_deg pointing into free space with lead_m, or fewer robots ([swarm] '
        'n_robots); nothing was written.'
    )
    require_clear_start(points, scene, radius, fix, place='the run-out beyond the goal')
