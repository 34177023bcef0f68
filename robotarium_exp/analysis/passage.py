"""A recorded trajectory seen from the tube: where each robot is along it, and whether the passage was observed.

:func:`along_tube` projects every position once, vectorised over frames and robots (NaN where a robot has no
position), and measures the swarm's density (:func:`vtube_planning.onboard.density.swarm_area`, the one definition) on
the frames where every robot has a position.

A recording may start after the swarm entered, end before it left, or show bodies that never came near the tube.
:func:`observed_passage` therefore gives a passing time only for a passage it saw whole: some robot before the
entrance (before any robot reached it), each robot inside the tube at some time, and each robot past the exit
after that. Otherwise the passing time is None, and the result says which part was not observed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.analysis.trajectory import Trajectory
from vtube_planning.geometry.scene import Scene
from vtube_planning.onboard import swarm_area

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class AlongTube:
    """Per frame (T,) and robot (N): arc length, clearance lambda - |y|, speed along the tube (NaN without a
    position), and the swarm's density (T,) (NaN on frames where some robot has no position)."""

    t_s: FloatArray
    l_m: FloatArray
    clearance_m: FloatArray
    forward_speed_mps: FloatArray
    density_per_m2: FloatArray
    complete: NDArray[np.bool_]


@dataclass(frozen=True)
class Passage:
    """The passage through the tube as observed.

    Attributes
    ----------
    passing_time_s
        First robot at the entrance to the last one past the exit; None unless the whole passage was observed.
    first_entry_s, last_exit_s
        When the first robot reached the entrance and the last observed exit (None when not seen).
    entrance_observed
        Some robot was seen before the entrance before any robot reached it.
    never_inside, not_exited
        Robots never seen inside the tube; robots not seen past the exit after being inside.
    robots_passed
        Robots seen inside and then past the exit.
    unobserved
        What was not observed, in words (empty when the passage was).
    """

    passing_time_s: float | None
    first_entry_s: float | None
    last_exit_s: float | None
    entrance_observed: bool
    never_inside: tuple[str, ...]
    not_exited: tuple[str, ...]
    robots_passed: int
    unobserved: tuple[str, ...]


def along_tube(trajectory: Trajectory, scene: Scene) -> AlongTube:
    """Project every position once (see the module docstring)."""
    positions = trajectory.positions_m
    steps, _, n = positions.shape
    present = trajectory.present()
    l_m, clearance = np.full((steps, n), np.nan), np.full((steps, n), np.nan)
    tangent = np.full((2, steps, n), np.nan)
    points = positions.transpose(1, 0, 2)[:, present]  # (2, number present)
    if points.shape[1]:
        projection = scene.tube.project(points)
        l_m[present], clearance[present] = projection.l_m, projection.clearance_m
        tangent[:, present] = projection.tangent
    velocity = np.gradient(positions, trajectory.t_s, axis=0) if steps > 1 else np.zeros_like(positions)
    forward = np.einsum('tin,itn->tn', velocity, tangent)
    complete = np.asarray(present.all(axis=1), dtype=bool)
    density = np.full(steps, np.nan)
    if complete.any():
        lc = l_m[complete]
        density[complete] = n / swarm_area(scene.tube, lc.min(axis=1), lc.max(axis=1), scene.swarm.r_a_m)
    return AlongTube(trajectory.t_s, l_m, clearance, forward, density, complete)


def observed_passage(along: AlongTube, length_m: float, robot_ids: tuple[str, ...]) -> Passage:
    """The passage as observed (module docstring); NaN entries of ``along`` are frames without a position."""
    t, l_m = along.t_s, along.l_m
    frames = np.arange(t.size)[:, None]
    reached = l_m >= 0.0
    first_entry = int(np.argmax(reached.any(axis=1))) if reached.any() else None
    entrance = first_entry is not None and bool((l_m[:first_entry] < 0.0).any())
    inside = reached & (l_m <= length_m) & (along.clearance_m >= 0.0)
    ever_inside = np.asarray(inside.any(axis=0), dtype=bool)
    first_inside = np.where(ever_inside, np.argmax(inside, axis=0), t.size)
    past = (l_m >= length_m) & (frames > first_inside)
    exited = np.asarray(past.any(axis=0), dtype=bool)
    exits = t[np.argmax(past, axis=0)]
    never_inside = tuple(r for r, seen in zip(robot_ids, ever_inside, strict=True) if not seen)
    not_exited = tuple(r for r, seen, out in zip(robot_ids, ever_inside, exited, strict=True) if seen and not out)
    unobserved = []
    if first_entry is None:
        unobserved.append('no robot was seen at or past the entrance')
    elif not entrance:
        unobserved.append('no robot was seen before the entrance before the first one reached it')
    if never_inside:
        unobserved.append(f'never seen inside the tube: {", ".join(never_inside)}')
    if not_exited:
        unobserved.append(f'not seen past the exit after being inside: {", ".join(not_exited)}')
    first_entry_s = float(t[first_entry]) if first_entry is not None else None
    last_exit_s = float(exits[exited].max()) if exited.all() else None
    return Passage(
        passing_time_s=last_exit_s - first_entry_s
        if not unobserved and last_exit_s is not None and first_entry_s is not None
        else None,
        first_entry_s=first_entry_s,
        last_exit_s=last_exit_s,
        entrance_observed=entrance,
        never_inside=never_inside,
        not_exited=not_exited,
        robots_passed=int(exited.sum()),
        unobserved=tuple(unobserved),
    )
