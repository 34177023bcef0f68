"""Robot bodies on a scene's obstacles or outside its workspace, over a whole run or at its start.

A scene made from a map (`vtube tube generate`) has obstacles and a workspace (the map); the tube is certified
clear of both, but the swarm flies before the entrance and beyond the exit too. A body (a disc of ``body_radius_m``
about a robot's centre) is on an obstacle where the centre's clearance to the obstacles is below the radius, and
outside the workspace where its signed clearance to the rectangle's edge is. Either is a failure of the run at any
time of it (`MapContact.failures`); a start formation with either is refused before the run (`require_clear_start`).

A robot that has passed the exit has left the swarm, not the map: the paper's model, which does not park, drives it
on at its speed until the last robot is through (the run ends then), across whatever lies beyond the goal. Its
contacts there fail the run too, counted apart because the fix differs (room beyond the goal, not a better tube).
The one exception (`fails_beyond_exit`): a simulation, which does not park, of a Robotarium scene, whose flight
parks its robots beyond the exit; its robots drive on where the flight's park, and the parking is judged by the
testbed's verdict (`vtube robotarium run`, `robotarium_exp.verdict`), so there they are told, not failed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import SceneError
from vtube_planning.geometry.scene import Scene

FloatArray = NDArray[np.float64]
First = tuple[float, float, float] | None
"""When and where a kind of contact first happened, (t, x, y); None: never."""

BEYOND_EXIT_FIX = (
    'the robots drive on beyond the goal until the last one is through: give them room there (a map file: move '
    'goal_m or goal_region_m of [tube.generate] away from the wall or the edge, or give goal_heading_deg pointing '
    'into free space with lead_m, or fewer robots: [swarm] n_robots; `vtube tube generate` checks the straight '
    'run-out)'
)
"""What to change where bodies touch beyond the exit."""


@dataclass(frozen=True)
class MapContact:
    """Robot-steps with a body on an obstacle and outside the workspace, and when and where each first happened
    (None: never; the scene has neither, or no robot touched it). ``on_obstacles`` and ``outside_workspace`` count
    the steps before a robot passed the exit; ``on_obstacles_after_exit`` and ``outside_after_exit`` those after it
    (``first_..._after_exit`` the first of those), where the paper's model, which does not park, drives on at its
    speed. Every one fails the run; those beyond the exit only where ``fails_beyond_exit`` (module doc)."""

    on_obstacles: int
    outside_workspace: int
    first_on_obstacle: First = None
    first_outside: First = None
    outside_after_exit: int = 0
    on_obstacles_after_exit: int = 0
    first_on_obstacle_after_exit: First = None
    first_outside_after_exit: First = None
    fails_beyond_exit: bool = True

    def failures(self) -> tuple[str, ...]:
        """One reason per kind of contact, before the exit and beyond it (empty: none)."""
        kinds = [
            (self.on_obstacles, self.first_on_obstacle, 'on an obstacle', ''),
            (self.outside_workspace, self.first_outside, 'outside the workspace (the map)', ''),
        ]
        if self.fails_beyond_exit:
            kinds += [
                (self.on_obstacles_after_exit, self.first_on_obstacle_after_exit, 'on an obstacle', 'beyond the exit'),
                (
                    self.outside_after_exit,
                    self.first_outside_after_exit,
                    'outside the workspace (the map)',
                    'beyond the exit',
                ),
            ]
        found, beyond = [], False
        for steps, first, what, where in kinds:
            if steps and first is not None:
                t, x, y = first
                said = f'robot bodies were {what} in {steps} robot-steps'
                said += f' {where}' if where else ''
                found.append(said + f' (first at t = {t:.2f} s, ({x:.2f}, {y:.2f}))')
                beyond = bool(where)
        if beyond:  # the fix once, after the last contact beyond the exit
            found[-1] += f': {BEYOND_EXIT_FIX}'
        return tuple(found)


def fails_beyond_exit(scene: Scene, *, parks: bool) -> bool:
    """Whether bodies on obstacles or off the map beyond the exit fail a run of ``scene`` (``parks``: the run parks
    its robots there, as a Robotarium flight does): always, but in a run that does not park (the paper's model,
    simulated) of a Robotarium scene, whose robots drive on where the flight's would park (module doc)."""
    return parks or scene.testbed != 'robotarium'


def map_contact(
    t_s: FloatArray,
    positions_m: FloatArray,
    scene: Scene,
    body_radius_m: float,
    l_m: FloatArray | None = None,
    *,
    parks: bool = False,
) -> MapContact:
    """The contacts of the (T, 2, N) positions at the times (T,) with ``scene``'s obstacles and workspace; with the
    robots' arc lengths ``l_m`` (T, N), the steps after a robot passed the exit apart (``parks``: the run parks its
    robots beyond the exit, `fails_beyond_exit`)."""
    n = positions_m.shape[2]
    points = positions_m.transpose(0, 2, 1).reshape(-1, 2)  # (T N, 2), step by step
    after = np.zeros(points.shape[0], dtype=bool)
    if l_m is not None:
        after = (np.fmax.accumulate(np.asarray(l_m, dtype=float), axis=0) > scene.tube.length_m).ravel()  # NaN: unseen

    def contact(clearance: FloatArray | None, steps: NDArray[np.bool_]) -> tuple[int, First]:
        touching = np.zeros(0, dtype=bool) if clearance is None else (np.asarray(clearance) < body_radius_m) & steps
        if not touching.any():
            return 0, None
        k = int(np.argmax(touching))
        return int(touching.sum()), (float(t_s[k // n]), float(points[k, 0]), float(points[k, 1]))

    obstacles = scene.obstacles.clearance(points) if scene.obstacles else None
    workspace = scene.workspace.clearance(points) if scene.workspace is not None else None
    (on, first_on), (out, first_out) = contact(obstacles, ~after), contact(workspace, ~after)
    (on_after, first_on_after), (out_after, first_out_after) = contact(obstacles, after), contact(workspace, after)
    return MapContact(
        on,
        out,
        first_on,
        first_out,
        outside_after_exit=out_after,
        on_obstacles_after_exit=on_after,
        first_on_obstacle_after_exit=first_on_after,
        first_outside_after_exit=first_out_after,
        fails_beyond_exit=fails_beyond_exit(scene, parks=parks),
    )


def require_clear_start(
    positions_m: FloatArray, scene: Scene, body_radius_m: float, fix: str, place: str = 'the start'
) -> None:
    """Refuse a start formation (2, N) (or the robots' places beyond the goal, ``place``) with a body on an
    obstacle or outside the workspace, naming where and ``fix``."""
    contact = map_contact(np.zeros(1), positions_m[None], scene, body_radius_m)
    for steps, first, what in (
        (contact.on_obstacles, contact.first_on_obstacle, 'on an obstacle'),
        (contact.outside_workspace, contact.first_outside, 'outside the workspace (the map)'),
    ):
        if steps and first is not None:
            msg = (
                f'scene {scene.name!r}: {place} puts {steps} robot bodies {what}, the first at ({first[1]:.2f}, '
                f'{first[2]:.2f}); {fix}'
            )
            raise SceneError(msg)
