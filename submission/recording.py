"""Run a script on a Robotarium simulator and record what the simulator itself held, for the preflight to verify.

    python -m submission.recording --simulator bundled|pypi [--seed N] [--testbed-model NAME] --record FILE.npz SCRIPT

``bundled`` resolves ``import rps`` to the bundled V2 simulator (`robotarium_exp.rps_alias`, seeded like it,
under the testbed model ``NAME``: `robotarium_exp.rps.testbed_model`),
``pypi`` to the installed PyPI simulator. Either way the script's ``Robotarium`` class is replaced by a subclass
that, at every ``step()`` after the initialization, copies the poses and the commands the simulator is about to
validate, and, when the script ends however it ends, writes them with the simulator's own counters (its error
dictionary, its iteration count) and whether the script called the end-of-script function, as a vtube trajectory
log (`vtube_planning.log`: ``t_s``, ``positions_m``, ``headings_rad``, ``commands`` [v; omega]).
Nothing the script prints or saves is read.
"""

from __future__ import annotations

import argparse
import importlib
import runpy
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from robotarium_exp import rps_alias
from robotarium_exp.recorder import as_its_generation, time_step_s
from submission.errors import CheckError
from vtube_planning.errors import LogError
from vtube_planning.log import LOG_FORMAT, LOG_VERSION, read_log
from vtube_planning.npzfile import write_npz

FloatArray = NDArray[np.float64]
Simulator = Literal['bundled', 'pypi']
KIND = 'preflight recording'


@dataclass(frozen=True, eq=False)
class SimulatorRecord:
    """What a simulator held over one run of a script.

    Attributes
    ----------
    poses, commands
        Per step after the initialization, what ``step()`` validated: poses (T, 3, N), commands [v; omega] (T, 2, N).
    dt_s
        The simulator's time step.
    errors
        Its error counters as it kept them (integers only).
    iterations, initialization_steps
        Its own count of steps, and how many of them the initialization took.
    robotariums
        Robotarium objects the script made (the testbed runs one).
    end_of_script
        The script called ``debug()`` / ``call_at_scripts_end()``.
    """

    poses: FloatArray
    commands: FloatArray
    dt_s: float
    errors: dict[str, int]
    iterations: int
    initialization_steps: int
    robotariums: int
    end_of_script: bool

    @property
    def experiment_steps(self) -> int:
        """Steps after the initialization, by the simulator's count."""
        return self.iterations - self.initialization_steps


class _Recorder:
    """The rows and counts of every recorded Robotarium object of this process."""

    def __init__(self) -> None:
        self.robots: list[Any] = []

    def write(self, path: Path, simulator: Simulator) -> None:
        robots = self.robots
        r = robots[0] if robots else None
        rows: list[tuple[FloatArray, FloatArray]] = [] if r is None else r.vtube_rows
        n = 0 if r is None else int(r.number_of_robots)
        poses = np.array([p for p, _ in rows]).reshape(len(rows), 3, n)
        commands = np.array([c for _, c in rows]).reshape(len(rows), 2, n)
        errors = {} if r is None else getattr(r, '_errors', None) or {}
        dt = 0.0 if r is None else time_step_s(r)
        meta: dict[str, object] = {
            'format': LOG_FORMAT,
            'version': LOG_VERSION,
            'kind': KIND,
            'simulator': simulator,
            'n_robots': n,
            'dt_s': dt,
            'errors': {str(k): int(v) for k, v in errors.items() if isinstance(v, (int, np.integer))},
            'iterations': 0 if r is None else _iterations(r),
            'initialization_steps': 0 if r is None else r.vtube_initialization_steps,
            'robotariums': len(robots),
            'end_of_script': r is not None and r.vtube_end_of_script,
            'finished': True,
        }
        arrays = {
            't_s': dt * np.arange(len(rows), dtype=float),
            'positions_m': poses[:, :2],
            'headings_rad': poses[:, 2],
            'commands': commands,
        }
        write_npz(path, arrays, meta)


def recorded(cls: type, recorder: _Recorder) -> type:
    """``cls`` that keeps, at each ``step()`` after the initialization, the poses and commands it validates."""

    class Recorded(cls):  # type: ignore[misc]  # a subclass of the class chosen at run time
        def __init__(self, *args: Any, **kwargs: Any) -> None:
            self.vtube_rows: list[tuple[FloatArray, FloatArray]] = []
            self.vtube_initialization_steps = 0
            self.vtube_end_of_script = False
            recorder.robots.append(self)
            super().__init__(*args, **kwargs)

        def step(self) -> Any:
            if getattr(self, 'initializing', False):
                self.vtube_initialization_steps += 1
            else:
                poses = getattr(self, '_poses', None)  # V2 keeps them private, the classic simulator public
                commands = getattr(self, '_velocities', None)
                poses = self.poses if poses is None else poses
                commands = self.velocities if commands is None else commands
                self.vtube_rows.append((np.array(poses, dtype=float), np.array(commands, dtype=float)))
            return super().step()

        def debug(self) -> Any:
            self.vtube_end_of_script = True
            return super().debug()

        def call_at_scripts_end(self) -> Any:
            self.vtube_end_of_script = True
            return super().call_at_scripts_end()

    return as_its_generation(Recorded, cls)


def _iterations(r: object) -> int:
    for name in ('_iteration', '_iterations'):  # V2, classic
        value = getattr(r, name, None)
        if isinstance(value, (int, np.integer)):
            return int(value)
    return 0


def read_record(path: str | Path) -> SimulatorRecord:
    """A recording written by this module's runner."""
    try:
        arrays, meta = read_log(path)
    except LogError as err:
        raise CheckError(str(err)) from err
    if meta.get('kind') != KIND:
        msg = f'{str(path)!r} is a vtube log of kind {meta.get("kind")!r}, not a {KIND}.'
        raise CheckError(msg)
    positions, headings = arrays['positions_m'], arrays['headings_rad']
    return SimulatorRecord(
        poses=np.concatenate([positions, headings[:, None, :]], axis=1),
        commands=np.asarray(arrays['commands'], dtype=float),
        dt_s=float(meta['dt_s']),
        errors={str(k): int(v) for k, v in meta['errors'].items()},
        iterations=int(meta['iterations']),
        initialization_steps=int(meta['initialization_steps']),
        robotariums=int(meta['robotariums']),
        end_of_script=bool(meta['end_of_script']),
    )


def install(simulator: Simulator, seed: int | None, recorder: _Recorder, testbed_model: str = 'ideal') -> None:
    """Make ``import rps.robotarium`` give the chosen simulator with the recording ``Robotarium`` (the bundled one
    under ``testbed_model``)."""
    if simulator == 'bundled':
        rps_alias.install(seed=seed, testbed_model=None if testbed_model == 'ideal' else testbed_model)
    elif seed is not None:
        rps_alias.seed_rps(seed)
    module = importlib.import_module('rps.robotarium')
    setattr(module, 'Robotarium', recorded(getattr(module, 'Robotarium'), recorder))  # noqa: B009,B010


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog='python -m submission.recording', description=__doc__.splitlines()[0])
    parser.add_argument('--simulator', choices=('bundled', 'pypi'), required=True)
    parser.add_argument('--seed', type=int, default=None, help='seed random and np.random (default: none)')
    parser.add_argument('--testbed-model', default='ideal', help='the bundled simulator under this testbed model')
    parser.add_argument('--record', type=Path, required=True, metavar='FILE.npz', help='where to write the record')
    parser.add_argument('script', type=Path, help='the script to run')
    args = parser.parse_args(argv)
    recorder = _Recorder()
    install(args.simulator, args.seed, recorder, args.testbed_model)
    sys.argv = [str(args.script)]
    try:
        runpy.run_path(str(args.script), run_name='__main__')
    finally:
        recorder.write(args.record, args.simulator)


if __name__ == '__main__':
    main()
