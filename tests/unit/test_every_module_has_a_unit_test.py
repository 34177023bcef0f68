"""Every module of the five packages is named, by its full dotted name in an import, by a file under tests/unit."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
UNIT = Path(__file__).resolve().parent
PACKAGES = ('vtube', 'vtube_planning', 'unicycle_mapping', 'robotarium_exp', 'submission')


def modules() -> list[str]:
    """The dotted name of every module of the packages, a package by its ``__init__``."""
    names = []
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob('*.py')):
            parts = path.relative_to(ROOT).with_suffix('').parts
            names.append('.'.join(parts[:-1] if parts[-1] == '__init__' else parts))
    return names


def imported_names(source: str) -> set[str]:
    """What a file's absolute imports name: ``import a.b`` names a.b; ``from a.b import c`` names a.b and a.b.c."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
            names.update(f'{node.module}.{alias.name}' for alias in node.names)
    return names


def test_imported_names_reads_both_forms_of_import() -> None:
    names = imported_names('import a.b\nfrom c.d import e, f as g\nfrom . import h\n')
    assert names == {'a.b', 'c.d', 'c.d.e', 'c.d.f'}


def test_the_modules_are_found() -> None:
    found = modules()
    assert {'vtube', 'vtube.__main__', 'vtube_planning.onboard.law', 'submission.builder'} <= set(found)
    assert len(found) == len(set(found))


def test_every_module_is_imported_by_a_unit_test() -> None:
    named: set[str] = set()
    for path in UNIT.rglob('*.py'):
        named |= imported_names(path.read_text(encoding='utf-8'))
    missing = [name for name in modules() if name not in named]
    assert not missing, (
        f'{len(missing)} modules have no unit test (no file under tests/unit imports them by name); '
        'add tests/unit/<package>/.../test_<module>.py for each:\n  ' + '\n  '.join(missing)
    )
