"""The one recorder of a run on a Robotarium class: what the simulator itself held at every step, as a vtube
trajectory log.

`recorded` subclasses the script's ``rps.robotarium.Robotarium`` (V2 or classic, ours or PyPI's, chosen at run time):
at each ``step()`` after the initialization it copies the poses and the commands [v; omega] the simulator is about
to validate (the true poses: under a testbed model, what ``get_poses`` hands out may differ), counts the
initialization's steps and notes the end-of-script call (``debug()`` / ``call_at_scripts_end()``). A `Recorder`
holds the Robotarium objects a script made; the first one's rows are the record (the testbed runs one), written as a
vtube trajectory log (`vtube_planning.log`: ``t_s``, ``positions_m``, ``headings_rad``, ``commands``; until it is
finished, every 100 steps to ``FILE.partial.npz``) and completed by `Recorder.finish` with the simulator's own
counters (its error counts, its iterations, the initialization's steps, the Robotarium objects made, whether the
script called the end-of-script function).

Two uses: ``rps_alias --log`` (`recording`: finished by the end-of-script call) and the preflight's runner
(`submission.recording`: finished when the script ends, however it ends).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from vtube_planning.log import LogWriter
from vtube_planning.npzfile import write_npz


def time_step_s(robotarium: object) -> float:
    """The control period of either generation's simulator (V2: ``TIME_STEP``, classic: ``time_step``), 0 if none."""
    for name in ('TIME_STEP', 'time_step'):
        value = getattr(robotarium, name, None)
        if isinstance(value, (int, float)):
            return float(value)
    return 0.0


def counters(robotarium: object) -> tuple[dict[str, int], int]:
    """The simulator's error counts (integers only: classic and PyPI keep texts beside them; ours gives every key)
    and its iterations, initialization included, of either generation."""
    errors = getattr(robotarium, 'errors', None)
    if not isinstance(errors, dict):
        errors = getattr(robotarium, '_errors', None) or {}
    counts = {str(k): int(v) for k, v in errors.items() if isinstance(v, (int, np.integer)) and not isinstance(v, bool)}
    for name in ('_iteration', '_iterations'):  # V2, classic
        value = getattr(robotarium, name, None)
        if isinstance(value, (int, np.integer)):
            return counts, int(value)
    return counts, 0


def initialization_steps(robot: Any) -> int:
    """The steps the initialization took: those the recorder counted, or the bundled simulator's own count where
    that is more (an initialization recalled from `robotarium_exp.rps.initialization_memo` takes no step)."""
    return max(int(robot.vtube_initialization_steps), int(getattr(robot, 'initialization_steps', 0)))


class Recorder:
    """The Robotarium objects of one script and the log of the first one's steps (module doc).

    ``path`` is the log; ``meta`` its description (``kind`` at least); with ``finish_at_end_of_script`` the
    first object's end-of-script call finishes it.
    """

    def __init__(self, path: str | Path, meta: Mapping[str, object], *, finish_at_end_of_script: bool = False) -> None:
        self.path = Path(path)
        self.robots: list[Any] = []
        self.finish_at_end_of_script = finish_at_end_of_script
        self._log = LogWriter(self.path, dict(meta))
        self._rows = 0

    def started(self, robot: Any) -> None:
        """A Robotarium object is being constructed (before its constructor runs: V2 initializes in it)."""
        robot.vtube_initialization_steps = 0
        robot.vtube_end_of_script = False
        self.robots.append(robot)

    def stepped(self, robot: Any) -> None:
        """``robot.step()`` is about to validate what it holds: counted while initializing, else recorded."""
        if getattr(robot, 'initializing', False):
            robot.vtube_initialization_steps += 1
            return
        if robot is not self.robots[0]:
            return
        poses = getattr(robot, '_poses', None)  # V2 keeps them private, the classic simulator public
        commands = getattr(robot, '_velocities', None)
        poses = np.array(robot.poses if poses is None else poses, dtype=float)
        commands = np.array(robot.velocities if commands is None else commands, dtype=float)
        dt = time_step_s(robot)
        self._log.meta.update(n_robots=int(poses.shape[1]), dt_s=dt)
        self._log.append(t_s=self._rows * dt, positions_m=poses[:2], headings_rad=poses[2], commands=commands)
        self._rows += 1

    def ended(self, robot: Any) -> None:
        """``robot`` called the end-of-script function."""
        robot.vtube_end_of_script = True
        if self.finish_at_end_of_script and robot is self.robots[0]:
            self.finish()

    def finish(self) -> Path:
        """Write the finished log with the first object's counters (an empty log if the script made none)."""
        r = self.robots[0] if self.robots else None
        errors, iterations = counters(r) if r is not None else ({}, 0)
        meta: dict[str, Any] = {
            'n_robots': int(getattr(r, 'number_of_robots', 0)),
            'dt_s': time_step_s(r),
            'errors': errors,
            'iterations': iterations,
            'initialization_steps': 0 if r is None else initialization_steps(r),
            'robotariums': len(self.robots),
            'end_of_script': r is not None and r.vtube_end_of_script,
            'finished': True,
        }
        if self._rows:
            self._log.flush(**meta)
            return self.path
        n = meta['n_robots']
        empty = {'t_s': np.zeros(0), 'positions_m': np.zeros((0, 2, n)), 'headings_rad': np.zeros((0, n))}
        write_npz(self.path, empty | {'commands': np.zeros((0, 2, n))}, {**self._log.meta, **meta})
        return self.path


def as_its_generation(subclass: type, base: type) -> type:
    """``subclass`` of ``base`` named as ``base``, keeping only the end-of-script call ``base``'s generation has
    (V2: ``debug``, classic: ``call_at_scripts_end``): scripts test for it."""
    for end_of_script in ('debug', 'call_at_scripts_end'):
        if not hasattr(base, end_of_script):
            delattr(subclass, end_of_script)
    subclass.__name__ = base.__name__
    return subclass


def recorded(cls: type, recorder: Recorder) -> type:
    """``cls`` whose objects ``recorder`` records (module doc)."""

    class Recorded(cls):  # type: ignore[misc, unused-ignore]  # a subclass of the class chosen at run time
        def __init__(self, *args: Any, **kwargs: Any) -> None:
            recorder.started(self)
            super().__init__(*args, **kwargs)

        def step(self) -> Any:
            recorder.stepped(self)
            return super().step()

        def debug(self) -> Any:
            recorder.ended(self)
            return super().debug()

        def call_at_scripts_end(self) -> Any:
            recorder.ended(self)
            return super().call_at_scripts_end()

    return as_its_generation(Recorded, cls)


def recording(cls: type, log_path: str) -> type:
    """``cls`` that also writes the poses and commands of every step to a vtube trajectory log at ``log_path``,
    completed by the script's end-of-script call (``rps_alias --log``)."""
    return recorded(cls, Recorder(log_path, {'kind': 'bundled robotarium'}, finish_at_end_of_script=True))
