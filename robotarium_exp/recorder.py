"""The recorder of a run on a Robotarium class: every pose it hands out, written to a vtube trajectory log.

`recording` subclasses either generation of ``rps.robotarium.Robotarium`` (V2 or classic, chosen at run
time); the log (`vtube_planning.log`) is completed with the validation counts by the end-of-script call, and
until then, or for a script that never makes it, the poses are in ``FILE.partial.npz``.
"""

from __future__ import annotations

from typing import Any

from vtube_planning.log import LogWriter


def time_step_s(robotarium: object) -> float:
    """The control period of either generation's simulator (V2: ``TIME_STEP``, classic: ``time_step``), 0 if none."""
    for name in ('TIME_STEP', 'time_step'):
        value = getattr(robotarium, name, None)
        if isinstance(value, (int, float)):
            return float(value)
    return 0.0


def as_its_generation(subclass: type, base: type) -> type:
    """``subclass`` of ``base`` named as ``base``, keeping only the end-of-script call ``base``'s generation has
    (V2: ``debug``, classic: ``call_at_scripts_end``): scripts test for it."""
    for end_of_script in ('debug', 'call_at_scripts_end'):
        if not hasattr(base, end_of_script):
            delattr(subclass, end_of_script)
    subclass.__name__ = base.__name__
    return subclass


def recording(cls: type, log_path: str) -> type:
    """``cls`` that also writes every pose it hands out to a vtube trajectory log (completed at the script's end)."""

    class Recording(cls):  # type: ignore[misc, unused-ignore]  # a subclass of the class chosen at run time
        def __init__(self, *args: Any, **kwargs: Any) -> None:
            super().__init__(*args, **kwargs)
            self._log = LogWriter(
                log_path, {'kind': 'bundled robotarium', 'n_robots': self.number_of_robots, 'dt_s': time_step_s(self)}
            )

        def _counts(self) -> tuple[dict[str, int], int]:
            """Validation counts and iterations of either generation (classic keeps them private, with texts)."""
            if hasattr(self, 'TIME_STEP'):  # V2
                return self.errors, self.iterations
            return {k: v for k, v in self._errors.items() if isinstance(v, int)}, self._iterations

        def get_poses(self) -> Any:
            poses = super().get_poses()
            if '_log' not in self.__dict__:  # V2's constructor drives the robots to their start: not the script's
                return poses
            steps = self._counts()[1] - getattr(self, 'initialization_steps', 0)
            self._log.append(t_s=steps * time_step_s(self), positions_m=poses[:2], headings_rad=poses[2])
            return poses

        def debug(self) -> Any:
            errors, iterations = self._counts()
            self._log.flush(errors=errors, iterations=iterations, finished=True)
            return super().debug()

        def call_at_scripts_end(self) -> Any:
            errors, iterations = self._counts()
            self._log.flush(errors=errors, iterations=iterations, finished=True)
            return super().call_at_scripts_end()

    return as_its_generation(Recording, cls)
