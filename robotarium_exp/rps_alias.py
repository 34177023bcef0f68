"""Run an unchanged ``rps`` script on the bundled simulator: make ``import rps...`` resolve to ours.

    python -m robotarium_exp.rps_alias [--classic] [--seed N] [--log FILE.npz] my_script.py [args...]

or, inside Python, ``install()`` before the script imports ``rps``. By default ``rps.robotarium.Robotarium`` behaves
as V2 (robots are driven from the chargers to the initial conditions); ``--classic`` gives the classic generation's
behaviour (robots start exactly at the initial conditions), as the PyPI simulator does. ``--seed`` makes the
simulator's randomness (charger slots, deadlock escapes) reproducible; ``--log`` makes the simulator record every
pose it hands out (a vtube ``.npz`` log, completed by the end-of-script call).
"""

from __future__ import annotations

import functools
import importlib
import runpy
import sys
import types

import numpy as np

MODULES = ('', '.robotarium', '.utilities', '.utilities.barrier_certificates', '.utilities.controllers',
           '.utilities.misc', '.utilities.transformations')


def install(*, classic: bool = False, seed: int | None = None, log_path: str | None = None) -> None:
    """Register the bundled simulator's modules under the names ``rps``, ``rps.robotarium``, ``rps.utilities...``."""
    for suffix in MODULES:
        sys.modules['rps' + suffix] = importlib.import_module('robotarium_exp.rps' + suffix)
    original = sys.modules['rps.robotarium']
    cls = original.ClassicRobotarium if classic else original.Robotarium
    defaults = {}
    if seed is not None:
        defaults['rng'] = np.random.default_rng(seed)
    if log_path is not None:
        defaults['log_path'] = log_path
    if defaults:
        cls = type(cls.__name__, (cls,), {'__init__': functools.partialmethod(cls.__init__, **defaults)})
    module = types.ModuleType('rps.robotarium', original.__doc__)
    module.__dict__.update({k: v for k, v in vars(original).items() if not k.startswith('__')})
    module.Robotarium = cls
    sys.modules['rps.robotarium'] = module
    sys.modules['rps'].robotarium = module


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
        print('usage: python -m robotarium_exp.rps_alias [--classic] [--seed N] [--log FILE] SCRIPT [ARGS...]',
              file=sys.stderr)
        raise SystemExit(2)
    install(classic=classic, seed=seed, log_path=log_path)
    sys.argv = args
    runpy.run_path(sys.argv[0], run_name='__main__')


if __name__ == '__main__':
    main()
