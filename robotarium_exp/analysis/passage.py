"""A recorded trajectory seen from the tube: where each robot is along it, and whether the passage was observed.

`along_tube` projects every position once, vectorised over frames and robots (NaN where a robot has no
position), and measures the swarm's density
([`vtube_planning.onboard.density.swarm_area`][vtube_planning.onboard.density.swarm_area], the one definition) on the
frames where every robot has a position.

A flight of ours on a Robotarium (the submission's files, ``vtube robotarium run``'s log) records where it began
(`FlightStart`, `robotarium_exp.flight.flight_start`): after the initialization, with every robot
already inside the tube. `recorded_passage` times it as the experiment does, with the one definition of
`vtube_planning.swarm.metrics.passage_times` (first robot at l >= 0 to the last at l >= L), from that start.

Any other recording may start after the swarm entered, end before it left, or show bodies that never came near the
tube. `observed_passage` therefore infers the start, and gives a passing time only for a passage it saw
whole: some robot before the entrance (before any robot reached it), each robot inside the tube at some time, and
each robot past the exit after that. Otherwise the passing time is None, and the result says which part was not
observed. Either result says how its start was known (``Passage.start``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.analysis.trajectory import Trajectory
from robotarium_exp.errors import AnalysisError
from vtube_planning.geometry.scene import Scene
from vtube_planning.onboard import swarm_area
from vtube_planning.swarm.metrics import crossing_times, passage_times

FloatArray = NDArray[np.float64]

INFERRED_START = 'start inferred from the data: the first robot to reach the entrance, when one was seen before it'
"""How `observed_passage` knows where the passage starts."""


@dataclass(frozen=True)
class FlightStart:
    """Where a recorded flight began (`robotarium_exp.flight.flight_start`).

    Attributes
    ----------
    iteration, robotarium_time_s
        The Robotarium's steps before the flight (the initialization, when one ran), and their time.
    t_s
        The flight's first period on the trajectory's clock (seconds from its first frame).
    """

    iteration: int
    robotarium_time_s: float
    t_s: float

    @classmethod
    def from_record(cls, record: Mapping[str, Any] | None, where: str, first_t_s: float = 0.0) -> FlightStart | None:
        """The start a log's description records (None: not recorded, as by earlier submissions); its ``t_s`` is on
        the log's clock, whose first row is at ``first_t_s``."""
        if record is None:
            return None
        try:
            start = cls(int(record['iteration']), float(record['robotarium_time_s']), float(record['t_s']) - first_t_s)
        except (KeyError, TypeError, ValueError) as err:
            msg = (
                f"{where}: the recorded flight start {record!r} is unreadable ({err!r}); it must hold 'iteration', "
                "'robotarium_time_s' and 't_s', as robotarium_exp.flight.flight_start writes them. Remove "
                "'flight_start' from the log's description to have the start inferred instead."
            )
            raise AnalysisError(msg) from err
        if not (start.iteration >= 0 and math.isfinite(start.t_s) and math.isfinite(start.robotarium_time_s)):
            msg = f'{where}: the recorded flight start {record!r} needs a step count >= 0 and finite times.'
            raise AnalysisError(msg)
        return start

    def to_record(self) -> dict[str, float | int]:
        """The fields, as a loader passes them on in a trajectory's ``source``."""
        return {'iteration': self.iteration, 'robotarium_time_s': self.robotarium_time_s, 't_s': self.t_s}

    def describe(self) -> str:
        """The start, in words (a simulation's: its first row, with nothing before it)."""
        before = (
            f'after an initialization of {self.iteration} steps ({self.robotarium_time_s:.2f} s)'
            if self.iteration
            else 'no initialization before it'
        )
        return f'start recorded by the flight at t = {self.t_s:.2f} s, {before}'


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
        Robots never seen inside the tube (from a recorded start: never at or past the entrance); robots not seen
        past the exit after being inside.
    robots_passed
        Robots seen inside and then past the exit.
    unobserved
        What was not observed, in words (empty when the passage was).
    start
        How the passage's start was known: recorded by the flight, or inferred (`INFERRED_START`).
    """

    passing_time_s: float | None
    first_entry_s: float | None
    last_exit_s: float | None
    entrance_observed: bool
    never_inside: tuple[str, ...]
    not_exited: tuple[str, ...]
    robots_passed: int
    unobserved: tuple[str, ...]
    start: str = INFERRED_START


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
        start=INFERRED_START,
    )


def recorded_passage(along: AlongTube, length_m: float, robot_ids: tuple[str, ...], start: FlightStart) -> Passage:
    """The passage of a flight that recorded its ``start``, timed as the experiment times it (module docstring) on
    the frames from the start on; NaN entries of ``along`` are frames without a position."""
    flown = along.t_s >= start.t_s - 1e-9  # the trajectory's clock is rounded to nanoseconds
    t, l_m = along.t_s[flown], along.l_m[flown]
    passing, _, passed, first_entry, last_exit = passage_times(t, l_m, length_m)
    entered = np.isfinite(crossing_times(t, l_m, 0.0))
    exited = np.isfinite(crossing_times(t, l_m, length_m))
    never = tuple(r for r, seen in zip(robot_ids, entered, strict=True) if not seen)
    not_exited = tuple(r for r, seen, out in zip(robot_ids, entered, exited, strict=True) if seen and not out)
    unobserved = []
    if never:
        unobserved.append(f'never seen at or past the entrance: {", ".join(never)}')
    if not_exited:
        unobserved.append(f'not seen past the exit: {", ".join(not_exited)}')
    before = t < first_entry if math.isfinite(first_entry) else np.zeros(t.size, dtype=bool)
    return Passage(
        passing_time_s=passing if math.isfinite(passing) else None,
        first_entry_s=first_entry if math.isfinite(first_entry) else None,
        last_exit_s=last_exit if math.isfinite(last_exit) else None,
        entrance_observed=bool((l_m[before] < 0.0).any()),
        never_inside=never,
        not_exited=not_exited,
        robots_passed=passed,
        unobserved=tuple(unobserved),
        start=start.describe(),
    )
