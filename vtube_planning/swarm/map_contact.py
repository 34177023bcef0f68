"""Robot bodies on a scene's obstacles or outside its workspace, over a whole run or at its start.

A scene made from a map (`vtube tube generate`) has obstacles and a workspace (the map); the tube is certified
clear of both, but the swarm flies before the entrance and beyond the exit too. A body (a disc of ``body_radius_m``
about a robot's centre) is on an obstacle where the centre's clearance to the obstacles is below the radius, and
outside the workspace where its signed clearance to the rectangle's edge is. Either is a failure of the run
(`MapContact.failures`) up to the robot's exit; a start formation with either is refused before the run
(`require_clear_start`).

A robot that has passed the exit has left the run: the paper's model, which does not park, drives it on at its speed
until the last robot is through (the run ends then), across whatever lies beyond the goal. Its contacts there are
counted apart and told, not failed; a flight that parks (the Robotarium's) is judged on its parking by the verdict of
the testbed (`robotarium_exp.fit`, the analysis's obstacle clearance), not here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import SceneError
from vtube_planning.geometry.scene import Scene

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class MapContact:
    """Robot-steps with a body on an obstacle and outside the workspace, and when and where each first happened
    (None: never; the scene has neither, or no robot touched it). ``on_obstacles`` and ``outside_workspace`` count
    the steps before a robot passed the exit; ``on_obstacles_after_exit`` and ``outside_after_exit`` those after it,
    where the robot has left the run and the paper's model, which does not park, drives on at its speed (told, not a
    failure: module doc)."""

    on_obstacles: int
    outside_workspace: int
    first_on_obstacle: tuple[float, float, float] | None = None
    first_outside: tuple[float, float, float] | None = None
    outside_after_exit: int = 0
    on_obstacles_after_exit: int = 0

    def failures(self) -> tuple[str, ...]:
        """One reason per kind of contact (empty: none)."""
        found = []
        for steps, first, what in (
            (self.on_obstacles, self.first_on_obstacle, 'on an obstacle'),
            (self.outside_workspace, self.first_outside, 'outside the workspace (the map)'),
        ):
            if steps and first is not None:
                t, x, y = first
                found.append(
                    f'robot bodies were {what} in {steps} robot-steps (first at t = {t:.2f} s, ({x:.2f}, {y:.2f}))'
                )
        return tuple(found)


def map_contact(
    t_s: FloatArray, positions_m: FloatArray, scene: Scene, body_radius_m: float, l_m: FloatArray | None = None
) -> MapContact:
    """The contacts of the (T, 2, N) positions at the times (T,) with ``scene``'s obstacles and workspace; with the
    robots' arc lengths ``l_m`` (T, N), the steps after a robot passed the exit apart."""
    n = positions_m.shape[2]
    points = positions_m.transpose(0, 2, 1).reshape(-1, 2)  # (T N, 2), step by step
    obstacles = scene.obstacles.clearance(points) if scene.obstacles else None
    workspace = scene.workspace.clearance(points) if scene.workspace is not None else None
    after = np.zeros(points.shape[0], dtype=bool)
    if l_m is not None:
        after = (np.fmax.accumulate(np.asarray(l_m, dtype=float), axis=0) > scene.tube.length_m).ravel()  # NaN: unseen
    beyond = [0, 0]
    for k, clearance in enumerate((obstacles, workspace)):
        if clearance is not None:
            beyond[k] = int(((clearance < body_radius_m) & after).sum())
    obstacles, workspace = (None if c is None else np.where(after, np.inf, c) for c in (obstacles, workspace))

    def contact(clearance: FloatArray | None) -> tuple[int, tuple[float, float, float] | None]:
        touching = np.zeros(0, dtype=bool) if clearance is None else np.asarray(clearance) < body_radius_m
        if not touching.any():
            return 0, None
        k = int(np.argmax(touching))
        return int(touching.sum()), (float(t_s[k // n]), float(points[k, 0]), float(points[k, 1]))

    (on, first_on), (out, first_out) = contact(obstacles), contact(workspace)
    return MapContact(on, out, first_on, first_out, outside_after_exit=beyond[1], on_obstacles_after_exit=beyond[0])


def require_clear_start(positions_m: FloatArray, scene: Scene, body_radius_m: float, fix: str) -> None:
    """Refuse a start formation (2, N) with a body on an obstacle or outside the workspace, naming where and
    ``fix``."""
    contact = map_contact(np.zeros(1), positions_m[None], scene, body_radius_m)
    for steps, first, what in (
        (contact.on_obstacles, contact.first_on_obstacle, 'on an obstacle'),
        (contact.outside_workspace, contact.first_outside, 'outside the workspace (the map)'),
    ):
        if steps and first is not None:
            msg = (
                f'scene {scene.name!r}: the start puts {steps} robot bodies {what}, the first at ({first[1]:.2f}, '
                f'{first[2]:.2f}); {fix}'
            )
            raise SceneError(msg)
