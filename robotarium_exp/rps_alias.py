"""Run an unchanged ``rps`` script on the bundled simulator: make ``import rps...`` resolve to ours.

    python -m robotarium_exp.rps_alias [--classic] my_script.py [args...]

or, inside Python, ``install()`` before the script imports ``rps``. By default ``rps.robotarium.Robotarium`` behaves
as V2 (robots are driven from the chargers to the initial conditions); ``--classic`` gives the classic generation's
behaviour (robots start exactly at the initial conditions), as the PyPI simulator does.
"""

from __future__ import annotations

import importlib
import runpy
import sys
import types

MODULES = ('', '.robotarium', '.utilities', '.utilities.barrier_certificates', '.utilities.controllers',
           '.utilities.misc', '.utilities.transformations')


def install(*, classic: bool = False) -> None:
    """Register the bundled simulator's modules under the names ``rps``, ``rps.robotarium``, ``rps.utilities...``."""
    for suffix in MODULES:
        sys.modules['rps' + suffix] = importlib.import_module('robotarium_exp.rps' + suffix)
    if classic:
        original = sys.modules['rps.robotarium']
        module = types.ModuleType('rps.robotarium', original.__doc__)
        module.__dict__.update({k: v for k, v in vars(original).items() if not k.startswith('__')})
        module.Robotarium = original.ClassicRobotarium
        sys.modules['rps.robotarium'] = module
        sys.modules['rps'].robotarium = module


def main() -> None:
    args = sys.argv[1:]
    classic = bool(args) and args[0] == '--classic'
    args = args[1:] if classic else args
    if not args:
        print('usage: python -m robotarium_exp.rps_alias [--classic] SCRIPT [ARGS...]', file=sys.stderr)
        raise SystemExit(2)
    install(classic=classic)
    sys.argv = args
    runpy.run_path(sys.argv[0], run_name='__main__')


if __name__ == '__main__':
    main()
