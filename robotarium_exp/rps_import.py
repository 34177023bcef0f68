"""How ``import rps...`` resolves to a generation of the bundled simulator: name by name, when the script imports it.

`RpsFinder` (first on ``sys.meta_path``) answers every ``rps`` and ``rps.*`` name: a module of the chosen
`Generation` is imported then, and registered under its ``rps`` name (the same module object, so state shared
between modules stays shared; a package is a new empty module, as the official packages are empty, so that
``from rps import robotarium`` imports ``rps.robotarium`` through the finder); a name the generation does not have is a ``ModuleNotFoundError``, as it would be on
the official simulator (and never a second copy of one of our own modules found on ``rps``'s path).

Importing lazily keeps what an import of the official modules does, when it does it: both official generations set
cvxopt's global solver options when their certificate modules are imported (``show_progress`` off, ``reltol`` and
``feastol`` 1e-2, ``maxiters`` 50), which silences and loosens every QP a script solves with cvxopt itself. V2 sets
them in ``rps.utilities.barrier_certificates``, which ``rps.robotarium`` imports; classic in
``rps.utilities.barrier_certificates`` and ``rps.utilities.barrier_certificates2``, and its ``rps.robotarium``
imports neither. `Generation.sets_qp_options` and `Generation.imports` record those facts; the finder
sets the options when such a name is first imported, so a script sees the options it would see there.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from types import ModuleType

import cvxopt

OFFICIAL_QP_OPTIONS = {'show_progress': False, 'reltol': 1e-2, 'feastol': 1e-2, 'maxiters': 50}
"""What both official generations write into ``cvxopt.solvers.options`` when a certificate module is imported."""


@dataclass(frozen=True)
class Generation:
    """One generation of ``rps``: our package for it, its modules (suffixes of ``rps``), the official modules whose
    import sets cvxopt's options and the official imports of those modules by others."""

    name: str
    package: str
    modules: tuple[str, ...]
    sets_qp_options: tuple[str, ...]
    imports: Mapping[str, tuple[str, ...]] = field(default_factory=dict)


V2 = Generation(
    'V2',
    'robotarium_exp.rps',
    (
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
    ),
    sets_qp_options=('.utilities.barrier_certificates',),
    imports={'.robotarium': ('.utilities.barrier_certificates',)},
)

CLASSIC = Generation(
    'classic',
    'robotarium_exp.rps_classic',
    (
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
    ),
    sets_qp_options=('.utilities.barrier_certificates', '.utilities.barrier_certificates2'),
)


def suffix_of(name: str) -> str | None:
    """``'.utilities.graph'`` for ``'rps.utilities.graph'``, ``''`` for ``'rps'``, None for a name outside rps."""
    if name == 'rps' or name.startswith('rps.'):
        return name[3:]
    return None


class RpsFinder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Resolves ``rps`` names to ``generation``'s modules, or to the ``replaced`` modules (by suffix)."""

    def __init__(self, generation: Generation, replaced: Mapping[str, ModuleType]) -> None:
        self.generation = generation
        self.replaced = dict(replaced)
        self._specs: dict[str, importlib.machinery.ModuleSpec | None] = {}

    def find_spec(
        self, fullname: str, path: object = None, target: object = None
    ) -> importlib.machinery.ModuleSpec | None:
        suffix = suffix_of(fullname)
        if suffix is None:
            return None  # not an rps name: the next finder's
        if suffix not in self.generation.modules:
            msg = f'No module named {fullname!r}'
            raise ModuleNotFoundError(msg, name=fullname)
        return importlib.machinery.ModuleSpec(fullname, self, is_package=hasattr(self._module(suffix), '__path__'))

    def _module(self, suffix: str) -> ModuleType:
        if suffix in self.replaced:
            return self.replaced[suffix]
        return importlib.import_module(self.generation.package + suffix)

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType | None:
        """The generation's module itself; for a package, None: a new empty package (the official packages are
        empty), whose submodules are imported, not already bound to it, so their imports reach this finder."""
        module = self._module(spec.name[3:])
        if hasattr(module, '__path__'):
            return None
        self._specs[spec.name] = module.__spec__  # importing sets __spec__ to the alias's; exec_module restores it
        return module

    def exec_module(self, module: ModuleType) -> None:
        name = module.__spec__.name if module.__spec__ else ''
        suffix = name[3:]
        if name in self._specs:
            module.__spec__ = self._specs.pop(name)
        else:
            module.__doc__ = self._module(suffix).__doc__
        for imported in self.generation.imports.get(suffix, ()):
            importlib.import_module('rps' + imported)
        if suffix in self.generation.sets_qp_options:
            cvxopt.solvers.options.update(OFFICIAL_QP_OPTIONS)


def use_generation(generation: Generation, replaced: Mapping[str, ModuleType]) -> None:
    """Make ``rps`` names resolve to ``generation`` from now on: forget the ``rps`` modules imported so far and any
    earlier finder of ours, put a new one first."""
    for name in [n for n in sys.modules if suffix_of(n) is not None]:
        del sys.modules[name]
    sys.meta_path[:] = [f for f in sys.meta_path if not isinstance(f, RpsFinder)]
    sys.meta_path.insert(0, RpsFinder(generation, replaced))


@contextmanager
def kept_apart() -> Iterator[None]:
    """Inside, a script may be given ``rps`` (`use_generation`) and the official imports may set cvxopt's
    options; after, the finders, the ``rps`` modules and cvxopt's options are what they were (a process that runs a
    script of its own, as the demo and the regression test do, goes on as before)."""
    finders, options = list(sys.meta_path), dict(cvxopt.solvers.options)
    modules = {name: module for name, module in sys.modules.items() if suffix_of(name) is not None}
    try:
        yield
    finally:
        sys.meta_path[:] = finders
        for name in [name for name in sys.modules if suffix_of(name) is not None]:
            del sys.modules[name]
        sys.modules.update(modules)
        cvxopt.solvers.options.clear()  # the dict cvxopt's solvers read: its contents restored, not another dict
        cvxopt.solvers.options.update(options)
