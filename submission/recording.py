"""Run a script on a Robotarium simulator and record what the simulator itself held, for the preflight to verify.

    python -m submission.recording --simulator bundled|pypi [--seed N] [--testbed-model NAME] [--reuse-initialization]
        [--salt HEX] --record FILE.npz SCRIPT

``bundled`` resolves ``import rps`` to the bundled V2 simulator (`robotarium_exp.rps_alias`, seeded like it,
under the testbed model ``NAME``: `robotarium_exp.rps.testbed_model`),
``pypi`` to the installed PyPI simulator; with ``--reuse-initialization`` the bundled simulator takes the state V2's
initialization leaves from the user's cache where an earlier run of the same start left it (`submission.reuse`:
bit for bit what the initialization would leave), and stores it there otherwise. Either way the script's
``Robotarium`` class is the one recorder's subclass (`robotarium_exp.recorder`: at every ``step()`` after the
initialization, the poses and the commands the simulator is about to validate), and when the script ends, however
it ends, the record is written with the simulator's own counters (its error counts, its iteration count) and
whether the script called the end-of-script function, as a vtube trajectory log (`vtube_planning.log`: ``t_s``,
``positions_m``, ``headings_rad``, ``commands`` [v; omega]). Nothing the script prints or saves is read.
"""

from __future__ import annotations

import argparse
import importlib
import runpy
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from robotarium_exp import rps_alias
from robotarium_exp.recorder import Recorder, recorded
from robotarium_exp.rps import initialization_memo
from submission.errors import CheckError
from submission.reuse import InitializedStates
from vtube_planning.errors import LogError
from vtube_planning.log import read_log

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


def recorder_for(path: str | Path, simulator: Simulator) -> Recorder:
    """The recorder of a preflight run on ``simulator``, writing its record to ``path``."""
    return Recorder(path, {'kind': KIND, 'simulator': simulator})


def install(
    simulator: Simulator,
    seed: int | None,
    recorder: Recorder,
    testbed_model: str = 'ideal',
    *,
    reuse: bool = False,
    salt: bytes | None = None,
) -> None:
    """Make ``import rps.robotarium`` give the chosen simulator with the recording ``Robotarium`` (the bundled one
    under ``testbed_model``, with the initialized states of `submission.reuse` when ``reuse``, under ``salt``: default
    `submission.reuse.simulator_salt`)."""
    if simulator == 'bundled':
        rps_alias.install(seed=seed, testbed_model=None if testbed_model == 'ideal' else testbed_model)
        initialization_memo.memo = InitializedStates(salt=salt) if reuse else None
    elif seed is not None:
        rps_alias.seed_rps(seed)
    module = importlib.import_module('rps.robotarium')
    setattr(module, 'Robotarium', recorded(getattr(module, 'Robotarium'), recorder))  # noqa: B009,B010


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog='python -m submission.recording', description=__doc__.splitlines()[0])
    parser.add_argument('--simulator', choices=('bundled', 'pypi'), required=True)
    parser.add_argument('--seed', type=int, default=None, help='seed random and np.random (default: none)')
    parser.add_argument('--testbed-model', default='ideal', help='the bundled simulator under this testbed model')
    parser.add_argument(
        '--reuse-initialization', action='store_true', help="the bundled simulator's initialized states from the cache"
    )
    parser.add_argument(
        '--salt',
        type=bytes.fromhex,
        default=None,
        metavar='HEX',
        help='the salt of the initialized states, as the check computed it once (default: computed here)',
    )
    parser.add_argument('--record', type=Path, required=True, metavar='FILE.npz', help='where to write the record')
    parser.add_argument('script', type=Path, help='the script to run')
    args = parser.parse_args(argv)
    recorder = recorder_for(args.record, args.simulator)
    install(args.simulator, args.seed, recorder, args.testbed_model, reuse=args.reuse_initialization, salt=args.salt)
    sys.argv = [str(args.script)]
    try:
        runpy.run_path(str(args.script), run_name='__main__')
    finally:
        recorder.finish()


if __name__ == '__main__':
    main()
