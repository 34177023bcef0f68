"""The onboard package: its exports are the defining objects; MODULES lists every module in dependency order,
each importing only numpy, scipy, the standard library and modules before it (what the builder inlines)."""

from __future__ import annotations

import ast
import importlib
import sys
from pathlib import Path

import vtube_planning.onboard as package


def test_every_export_is_the_object_of_its_defining_module() -> None:
    for name in package.__all__:
        value = getattr(package, name)
        if name == 'MODULES':
            continue
        home = getattr(value, '__module__', None)
        if home is not None and home.startswith('vtube_planning.onboard.'):
            assert getattr(importlib.import_module(home), name) is value, name
        else:  # constants: found in exactly one listed module
            homes = [m for m in package.MODULES if getattr(importlib.import_module(m), name, None) is value]
            assert homes, name


def test_modules_lists_every_module_and_each_imports_only_earlier_ones() -> None:
    folder = Path(package.__file__).parent
    on_disk = {f'vtube_planning.onboard.{p.stem}' for p in folder.glob('*.py') if p.stem != '__init__'}
    assert set(package.MODULES) == on_disk and len(package.MODULES) == len(on_disk)
    for k, module in enumerate(package.MODULES):
        tree = ast.parse((folder / f'{module.rsplit(".", 1)[1]}.py').read_text())
        imported = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module}
        imported |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
        inner = {m for m in imported if m.startswith('vtube_planning')}
        assert inner <= set(package.MODULES[:k]), (module, inner - set(package.MODULES[:k]))
        outer = {m.split('.')[0] for m in imported} - {'vtube_planning', '__future__'}
        assert outer <= {'numpy', 'scipy'} | sys.stdlib_module_names, (module, outer)
