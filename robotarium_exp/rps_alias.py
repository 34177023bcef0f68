"""Run an unchanged ``rps`` script on the bundled simulator: make ``import rps...`` resolve to ours.

    python -m robotarium_exp.rps_alias [--classic] [--seed N] [--log FILE.npz] [--exact-qp]
                                       [--testbed-model NAME] my_script.py [args...]

or, inside Python, ``install()`` before the script imports ``rps``. By default ``rps`` is V2
(:mod:`robotarium_exp.rps`: robots are driven from the chargers to the initial conditions, ``debug()``);
``--classic`` makes it the classic generation, :mod:`robotarium_exp.rps_classic`, names and semantics (the PyPI
``robotarium_python_simulator`` 0.0.0: ``call_at_scripts_end()``, ``rps.robotarium_abc``,
``rps.utilities.barrier_certificates2``...). ``--seed`` seeds ``random`` and ``np.random``, what the scripts and
both generations draw from (V2's charger slots and deadlock escapes, classic's random start poses); ``--log`` makes
the simulator record every pose it hands out (:mod:`robotarium_exp.recorder`);
``--exact-qp`` makes the barrier certificates solve their QPs exactly and faster, instead of as the testbed does
(:func:`robotarium_exp.rps.utilities.barrier_certificates.use_qp_solver`); ``--testbed-model`` makes the
simulator act like the real robots (``ideal``, the default, ``fitted``, ``fitted:K``:
:mod:`robotarium_exp.rps.testbed_model`).

A script that dies on ``np.mat`` (removed in numpy 2, used by several classic examples) gets a message naming the
fix instead of a bare ``AttributeError``, and exit code 1.
"""

from __future__ import annotations

import argparse
import importlib
import random
import runpy
import sys
import traceback
import types
from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.recorder import recording
from robotarium_exp.rps.testbed_model import NAMES, TestbedModel, TestbedModelError, testbed_model
from robotarium_exp.rps.utilities.barrier_certificates import use_qp_solver

MODULES = (
    '',
    '.robotarium',
    '.robotarium_abc',
    '.utilities',
    '.utilities.barrier_certificates',
    '.utilities.controllers',
    '.utilities.graph',
    '.utilities.misc',
    '.utilities.sensors',
    '.utilities.transformations',
    '.examples',
    '.examples.state_estimation',
    '.examples.state_estimation.extended_kalman_filter',
    '.examples.state_estimation.extended_kalman_filter.uni_ekf',
)
"""The V2 package's modules (suffixes of ``rps``)."""

CLASSIC_MODULES = (
    '',
    '.robotarium',
    '.robotarium_abc',
    '.utilities',
    '.utilities.barrier_certificates',
    '.utilities.barrier_certificates2',
    '.utilities.controllers',
    '.utilities.graph',
    '.utilities.misc',
    '.utilities.transformations',
)
"""The classic package's modules (no examples package; one more certificate module)."""


def install(
    *,
    classic: bool = False,
    seed: int | None = None,
    log_path: str | None = None,
    testbed_model: str | TestbedModel | None = None,
) -> None:
    """Register the bundled simulator's modules under the names ``rps``, ``rps.robotarium``, ``rps.utilities...``.

    ``testbed_model``: the model every ``Robotarium()`` of the script gets unless it names one (either generation).
    """
    package, suffixes = ('robotarium_exp.rps_classic', CLASSIC_MODULES) if classic else ('robotarium_exp.rps', MODULES)
    for suffix in suffixes:
        sys.modules['rps' + suffix] = importlib.import_module(package + suffix)
    original = sys.modules['rps.robotarium']
    cls = original.Robotarium
    if seed is not None:
        seed_rps(seed)
    if testbed_model is not None:
        cls = with_testbed_model(cls, testbed_model)
    if log_path is not None:
        cls = recording(cls, log_path)
    module = types.ModuleType('rps.robotarium', original.__doc__)
    module.__dict__.update({k: v for k, v in vars(original).items() if not k.startswith('__')})
    module.__dict__['Robotarium'] = cls
    sys.modules['rps.robotarium'] = module
    vars(sys.modules['rps'])['robotarium'] = module


def with_testbed_model(cls: type, model: str | TestbedModel) -> type:
    """``cls`` (either generation's Robotarium) whose instances get ``testbed_model=model`` unless the script passes one."""
    chosen = testbed_model(model)

    class WithTestbedModel(cls):  # type: ignore[misc, unused-ignore]  # a subclass of the class chosen at run time
        def __init__(self, *args: Any, **kwargs: Any) -> None:
            kwargs.setdefault('testbed_model', chosen)
            super().__init__(*args, **kwargs)

    WithTestbedModel.__name__ = cls.__name__
    return WithTestbedModel


def seed_rps(seed: int) -> None:
    """Seed what ``rps`` and the scripts draw from: Python's ``random`` (charger slots) and ``np.random``."""
    random.seed(seed)
    np.random.seed(seed)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog='python -m robotarium_exp.rps_alias',
        description="Run an unchanged Robotarium script with `import rps` resolved to vtube's simulator.",
        epilog='Options go before the script; what follows the script is passed to it.',
    )
    parser.add_argument('--classic', action='store_true', help='the classic generation (call_at_scripts_end)')
    parser.add_argument('--seed', type=_seed, default=None, help='seed random and np.random, >= 0 (default: none)')
    parser.add_argument('--log', default=None, metavar='FILE.npz', help='record every pose handed out to this log')
    parser.add_argument('--exact-qp', action='store_true', help='solve the certificates exactly (DAQP), not as V2')
    parser.add_argument(
        '--testbed-model', type=_model, default=None, metavar='NAME', help=f'what the real robots do: {NAMES}'
    )
    parser.add_argument('command', nargs=argparse.REMAINDER, metavar='SCRIPT [ARGS ...]', help='the script to run')
    return parser


def _seed(text: str) -> int:
    if not text.isdigit() or int(text) >= 2**32:
        msg = f'{text!r} is not a seed from 0 to 2**32 - 1 (np.random.seed takes 32 bits)'
        raise argparse.ArgumentTypeError(msg)
    return int(text)


def _model(text: str) -> TestbedModel:
    try:
        return testbed_model(text)
    except TestbedModelError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def main() -> None:
    parser = _parser()
    args = parser.parse_args()
    if not args.command:
        parser.error('give the script to run, e.g. python -m robotarium_exp.rps_alias my_script.py')
    script = Path(args.command[0])
    if not script.is_file():
        parser.error(f'{script}: no such script; give the path of a Python file.')
    try:
        compile(script.read_bytes(), str(script), 'exec')
    except (SyntaxError, ValueError) as err:  # ValueError: null bytes
        parser.error(f'{script} is not a Python script ({err}).')
    if args.exact_qp:
        use_qp_solver('exact')
    install(classic=args.classic, seed=args.seed, log_path=args.log, testbed_model=args.testbed_model)
    sys.argv = list(args.command)
    try:
        runpy.run_path(sys.argv[0], run_name='__main__')
    except AttributeError as error:
        if not uses_np_mat(error):
            raise
        traceback.print_exc()
        print(NP_MAT_MESSAGE.format(script=sys.argv[0], numpy=np.__version__), file=sys.stderr)
        raise SystemExit(1) from None


NP_MAT_MESSAGE = (
    'rps_alias: {script} uses np.mat, which numpy 2 removed (numpy {numpy} is installed), so it fails on any '
    "simulator. Fix: replace np.mat('1 2; 3 4') by np.asmatrix('1 2; 3 4'), or better by a plain array, "
    'np.array([[1, 2], [3, 4]]).'
)


def uses_np_mat(error: AttributeError) -> bool:
    """Whether ``error`` is numpy 2 refusing ``np.mat`` (its message names it; the attribute is ``mat``)."""
    return getattr(error, 'name', None) == 'mat' or '`np.mat`' in str(error) or "attribute 'mat'" in str(error)


if __name__ == '__main__':
    main()
