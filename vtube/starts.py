"""Where a simulated swarm starts: the given positions, a Robotarium scene's entry formation (as its flight starts),
or the simulator's grid; refused where a body would start on an obstacle or off the map."""

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

__all__ = ['GRID_START', 'ROBOTARIUM_START', 'START_FIX', 'require_room_to_start', 'robotarium_start', 'started']


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


def require_room_to_start(scene: Scene, map_file: str) -> None:
    """Refuse a scene generated from ``map_file`` whose swarm could not start in free space inside the map: the
    Robotarium's entry formation (bodies r_p), else the simulator's grid before the entrance, unjittered, each body
    r_p and three standard deviations of the simulator's default jitter (so that a simulation's start, checked again
    with its own jitter, finds room at any seed but in the rarest)."""
    swarm = scene.swarm
    robotarium = robotarium_start(scene, swarm)
    if robotarium is not None:
        positions, radius = robotarium, swarm.r_p_m
    else:
        positions = initial_formation(scene.tube, swarm, np.random.default_rng(0), 0.0)
        radius = swarm.r_p_m + 3.0 * SimConfig().jitter_m
    depth = float(np.ptp(scene.tube.project(positions).l_m)) + 2.0 * swarm.r_a_m
    heading = math.degrees(math.atan2(*scene.tube.tangent(0.0)[::-1]))
    fix = (
        f'the {swarm.n_robots} robots start in a formation {depth:.1f} m deep before the entrance, behind start_m along '
        f"the tube's first heading ({heading:.0f} degrees): in {map_file}, move start_m (or start_region_m) of "
        '[tube.generate] to where that much room lies behind it, or give start_heading_deg pointing away from the '
        'obstacle with lead_m, or fewer robots ([swarm] n_robots); nothing was written.'
    )
    require_clear_start(positions, scene, radius, fix)
