"""Run an unchanged ``rps`` script on the bundled simulator: make ``import rps...`` resolve to ours.

    python -m robotarium_exp.rps_alias [--classic] [--seed N] [--log FILE.npz] [--exact-qp]
                                       [--testbed-model NAME] [--numpy1-names] [--sim-clock]
                                       my_script.py [args...]

or, inside Python, ``install()`` before the script imports ``rps``. By default ``rps`` is V2
(`robotarium_exp.rps`: robots are driven from the chargers to the initial conditions, ``debug()``);
``--classic`` makes it the classic generation, `robotarium_exp.rps_classic`, names and semantics (the PyPI
``robotarium_python_simulator`` 0.0.0: ``call_at_scripts_end()``, ``rps.robotarium_abc``,
``rps.utilities.barrier_certificates2``...). ``--seed`` seeds ``random`` and ``np.random``, what the scripts and
both generations draw from (V2's charger slots and deadlock escapes, classic's random start poses); ``--log`` makes
the simulator record the poses and commands of every step (`robotarium_exp.recorder`);
``--exact-qp`` makes the barrier certificates solve their QPs exactly and faster, instead of as the testbed does
(`robotarium_exp.rps.utilities.barrier_certificates.use_qp_solver`); ``--testbed-model`` makes the
simulator act like the real robots (``ideal``, the default, ``fitted``, ``fitted:K``:
`robotarium_exp.rps.testbed_model`); ``--numpy1-names`` gives back the numpy 1 names classic-era scripts use and
numpy 2 removed (``np.mat``...: `robotarium_exp.numpy1_names`), saying so on stderr; ``--sim-clock`` makes
``time.time()`` a simulated clock that advances by the time step at each ``step()`` (`robotarium_exp.sim_clock`),
so scripts that feed wall-clock time into their control run the same on every run and machine.

The script runs as ``python my_script.py`` would run it (its folder first on ``sys.path``, so modules beside it
import; ``__file__``; ``sys.argv``). A script that dies on ``np.mat`` (removed in numpy 2, used by several classic
examples) without ``--numpy1-names`` gets a message naming the fixes instead of a bare ``AttributeError``, and one that imports a name only the
other generation has (``cycle_GL`` without ``--classic``, ``create_si_barrier_certificate`` with it) gets one line
saying so and naming ``--classic``; both exit with code 1.
"""

from __future__ import annotations

import argparse
import builtins
import importlib
import os
import random
import re
import sys
import traceback
import types
from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.numpy1_names import notice, provide
from robotarium_exp.recorder import recording
from robotarium_exp.rps.testbed_model import NAMES, TestbedModel, TestbedModelError, testbed_model
from robotarium_exp.rps.utilities.barrier_certificates import use_qp_solver
from robotarium_exp.rps_import import CLASSIC, V2, Generation, suffix_of, use_generation
from robotarium_exp.sim_clock import START_S, SimClock, ticking


def install(
    *,
    classic: bool = False,
    seed: int | None = None,
    log_path: str | None = None,
    testbed_model: str | TestbedModel | None = None,
    clock: SimClock | None = None,
) -> None:
    """Make ``rps``, ``rps.robotarium``, ``rps.utilities...`` resolve to the bundled simulator's modules, each when
    the script first imports it (`robotarium_exp.rps_import`: so that cvxopt's options are set when the
    official modules would set them). ``rps`` modules imported before are forgotten.

    ``testbed_model``: the model every ``Robotarium()`` of the script gets unless it names one (either generation).
    ``clock``: advanced by the time step at every ``step()`` of every ``Robotarium()`` (`robotarium_exp.sim_clock`;
    installing it as ``time.time`` is the caller's).
    """
    generation = CLASSIC if classic else V2
    if seed is not None:
        seed_rps(seed)
    original = importlib.import_module(generation.package + '.robotarium')
    cls = original.Robotarium
    if testbed_model is not None:
        cls = with_testbed_model(cls, testbed_model)
    if clock is not None:
        cls = ticking(cls, clock)
    if log_path is not None:
        cls = recording(cls, log_path)
    module = types.ModuleType('rps.robotarium', original.__doc__)  # a copy: what the script rebinds stays its own
    module.__dict__.update({k: v for k, v in vars(original).items() if not k.startswith('__')})
    module.__dict__['Robotarium'] = cls
    use_generation(generation, {'.robotarium': module})


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
    parser.add_argument(
        '--log', default=None, metavar='FILE.npz', help='record the poses and commands of every step to this log'
    )
    parser.add_argument('--exact-qp', action='store_true', help='solve the certificates exactly (DAQP), not as V2')
    parser.add_argument(
        '--testbed-model', type=_model, default=None, metavar='NAME', help=f'what the real robots do: {NAMES}'
    )
    parser.add_argument(
        '--numpy1-names', action='store_true', help='give back np.mat and the other numpy 1 names numpy 2 removed'
    )
    parser.add_argument(
        '--sim-clock', action='store_true', help='time.time() advances by the time step per step(), from 0'
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
    if args.numpy1_names:
        print(notice(provide(np), np.__version__), file=sys.stderr)
    clock = SimClock() if args.sim_clock else None
    install(classic=args.classic, seed=args.seed, log_path=args.log, testbed_model=args.testbed_model, clock=clock)
    if clock is not None:
        print(
            f'rps_alias: --sim-clock: time.time() starts at {START_S} s and advances one time step per step().',
            file=sys.stderr,
        )
        clock.install()
    try:
        run_script(script, list(args.command))
    except AttributeError as error:
        if not uses_np_mat(error):
            raise
        traceback.print_exc()
        print(
            NP_MAT_MESSAGE.format(script=script, numpy=np.__version__, classic='--classic ' * args.classic),
            file=sys.stderr,
        )
        raise SystemExit(1) from None
    except ImportError as error:
        hint = other_generation_hint(error, script, CLASSIC if args.classic else V2)
        if hint is None:
            raise
        print(hint, file=sys.stderr)
        raise SystemExit(1) from None
    finally:
        if clock is not None:
            clock.uninstall()


def run_script(script: Path, argv: list[str]) -> None:
    """Run ``script`` as ``python script`` would: as ``__main__``, its folder (symbolic links resolved) first on
    ``sys.path`` in place of the folder ``python -m`` put there, ``__file__`` its absolute path, ``sys.argv``
    the script and its arguments."""
    folder = str(script.resolve().parent)
    if sys.path and sys.path[0] in ('', os.getcwd()):
        sys.path[0] = folder
    else:
        sys.path.insert(0, folder)
    sys.argv = argv
    path = os.path.join(os.getcwd(), script)  # as python sets __file__: absolute, not normalised
    main_module = types.ModuleType('__main__')
    main_module.__dict__.update({'__file__': path, '__builtins__': builtins, '__cached__': None})
    sys.modules['__main__'] = main_module
    exec(compile(script.read_bytes(), path, 'exec'), main_module.__dict__)  # noqa: S102 - running the script is the point


def other_generation_hint(error: ImportError, script: Path, generation: Generation) -> str | None:
    """One line naming ``--classic`` if ``error`` is the script importing an ``rps`` name that only the other
    generation has; None otherwise (a name neither has, or not an ``rps`` import)."""
    module = error.name or ''
    if module.startswith(generation.package):  # a name missing from one of our modules, named by its own name
        module = 'rps' + module[len(generation.package) :]
    suffix = suffix_of(module)
    if suffix is None:
        return None
    other = V2 if generation is CLASSIC else CLASSIC
    imported = re.match(r"cannot import name '(\w+)'", str(error))
    if imported is None:
        what, there = f'the module {module}', suffix in other.modules
    else:
        name = imported.group(1)
        what = f'{name} from {module}'
        there = f'{suffix}.{name}' in other.modules or (
            suffix in other.modules and hasattr(importlib.import_module(other.package + suffix), name)
        )
    if not there:
        return None
    flag = '--classic ' if other is CLASSIC else ''
    return (
        f'rps_alias: {script} imports {what}, which only the {other.name} generation of rps has; run it '
        f'{"with" if flag else "without"} --classic: python -m robotarium_exp.rps_alias {flag}{script}'
    )


NP_MAT_MESSAGE = (
    'rps_alias: {script} uses np.mat, which numpy 2 removed (numpy {numpy} is installed), so it fails on any '
    "simulator. Fix: replace np.mat('1 2; 3 4') by np.asmatrix('1 2; 3 4'), or better by a plain array, "
    'np.array([[1, 2], [3, 4]]); or run it unchanged with --numpy1-names: python -m robotarium_exp.rps_alias '
    '{classic}--numpy1-names {script}'
)


def uses_np_mat(error: AttributeError) -> bool:
    """Whether ``error`` is numpy 2 refusing ``np.mat`` (its message names it; the attribute is ``mat``)."""
    return getattr(error, 'name', None) == 'mat' or '`np.mat`' in str(error) or "attribute 'mat'" in str(error)


if __name__ == '__main__':
    main()
