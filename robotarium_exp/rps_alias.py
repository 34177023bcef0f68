"""Run an unchanged ``rps`` script on the bundled simulator: make ``import rps...`` resolve to ours.

    python -m robotarium_exp.rps_alias [--classic] [--seed N] [--log FILE.npz] my_script.py [args...]

or, inside Python, ``install()`` before the script imports ``rps``. By default ``rps.robotarium.Robotarium`` behaves
as V2 (robots are driven from the chargers to the initial conditions); ``--classic`` gives the classic generation's
behaviour (robots start exactly at the initial conditions), as the PyPI simulator does. ``--seed`` makes the
simulator's randomness (charger slots, deadlock escapes) reproducible; ``--log`` makes the simulator record every
pose it hands out (a vtube ``.npz`` log, completed by the end-of-script call).
"""

from __future__ import annotations

import importlib
import random
import runpy
import sys
import types
from typing import Any

import numpy as np

from vtube_planning.swarm.log import LogWriter

MODULES = (
    '',
    '.robotarium',
    '.robotarium_abc',
    '.utilities',
    '.utilities.barrier_certificates',
    '.utilities.controllers',
    '.utilities.graph',
    '.utilities.misc',
    '.utilities.transformations',
    '.examples',
    '.examples.state_estimation',
    '.examples.state_estimation.extended_kalman_filter',
    '.examples.state_estimation.extended_kalman_filter.uni_ekf',
)


def install(*, classic: bool = False, seed: int | None = None, log_path: str | None = None) -> None:
    """Register the bundled simulator's modules under the names ``rps``, ``rps.robotarium``, ``rps.utilities...``."""
    for suffix in MODULES:
        sys.modules['rps' + suffix] = importlib.import_module('robotarium_exp.rps' + suffix)
    original = sys.modules['rps.robotarium']
    cls = original.ClassicRobotarium if classic else original.Robotarium
    if seed is not None:
        seed_rps(seed)
    if log_path is not None:
        cls = recording(cls, log_path)
    module = types.ModuleType('rps.robotarium', original.__doc__)
    module.__dict__.update({k: v for k, v in vars(original).items() if not k.startswith('__')})
    module.__dict__['Robotarium'] = cls
    sys.modules['rps.robotarium'] = module
    vars(sys.modules['rps'])['robotarium'] = module


def seed_rps(seed: int) -> None:
    """Seed what ``rps`` and the scripts draw from: Python's ``random`` (charger slots) and ``np.random``."""
    random.seed(seed)
    np.random.seed(seed)


def recording(cls: type, log_path: str) -> type:
    """``cls`` that also writes every pose it hands out to a vtube trajectory log (completed at the script's end)."""

    class Recording(cls):  # a subclass of the class chosen at run time
        def __init__(self, *args: Any, **kwargs: Any) -> None:
            super().__init__(*args, **kwargs)
            self._log = LogWriter(
                log_path, {'kind': 'bundled robotarium', 'n_robots': self.number_of_robots, 'dt_s': self.TIME_STEP}
            )

        def get_poses(self) -> Any:
            poses = super().get_poses()
            self._log.append(
                t_s=(self.iterations - self.initialization_steps) * self.TIME_STEP,
                positions_m=poses[:2],
                headings_rad=poses[2],
            )
            return poses

        def debug(self) -> Any:
            self._log.flush(errors=self.errors, iterations=self.iterations, finished=True)
            return super().debug()

        def call_at_scripts_end(self) -> Any:
            self._log.flush(errors=self.errors, iterations=self.iterations, finished=True)
            return super().call_at_scripts_end()

    Recording.__name__ = cls.__name__
    return Recording


def main() -> None:
    args = sys.argv[1:]
    classic, seed, log_path = False, None, None
    while args and args[0] in ('--classic', '--seed', '--log'):
        if args[0] == '--classic':
            classic, args = True, args[1:]
        elif args[0] == '--seed':
            seed, args = int(args[1]), args[2:]
        else:
            log_path, args = args[1], args[2:]
    if not args:
        print(
            'usage: python -m robotarium_exp.rps_alias [--classic] [--seed N] [--log FILE] SCRIPT [ARGS...]',
            file=sys.stderr,
        )
        raise SystemExit(2)
    install(classic=classic, seed=seed, log_path=log_path)
    sys.argv = args
    runpy.run_path(sys.argv[0], run_name='__main__')


if __name__ == '__main__':
    main()
