"""The imports of the five packages' modules, read from their sources with ``ast``: the graph of which module imports
which (`import_graph`), everywhere in a module or only what runs when it is imported.

An import names a module (``from a.b import c`` names ``a.b.c`` when that is a module, else ``a.b``); a package is
its ``__init__``; relative imports are resolved. "At import" leaves out the imports inside functions and under
``if TYPE_CHECKING:`` (what runs is the module's body, the bodies of its classes and of its other blocks).
"""

from __future__ import annotations

import ast
import functools
from collections.abc import Iterator, Mapping
from pathlib import Path

PACKAGES = ('vtube', 'vtube_planning', 'unicycle_mapping', 'robotarium_exp', 'submission')


def module_files(root: Path, packages: tuple[str, ...] = PACKAGES) -> dict[str, tuple[Path, bool]]:
    """Dotted name -> (file, is a package's ``__init__``) for every module of ``packages`` under ``root``."""
    found = {}
    for package in packages:
        for path in sorted((root / package).rglob('*.py')):
            parts = path.relative_to(root).with_suffix('').parts
            is_package = parts[-1] == '__init__'
            found['.'.join(parts[:-1] if is_package else parts)] = (path, is_package)
    return found


def _type_checking(node: ast.If) -> bool:
    test = node.test
    return (isinstance(test, ast.Name) and test.id == 'TYPE_CHECKING') or (
        isinstance(test, ast.Attribute) and test.attr == 'TYPE_CHECKING'
    )


def import_nodes(tree: ast.AST, *, at_import_only: bool = False) -> Iterator[ast.Import | ast.ImportFrom]:
    """Every import statement of ``tree``, or only those that run when the module is imported."""
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node
        elif at_import_only and isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            continue
        elif at_import_only and isinstance(node, ast.If) and _type_checking(node):
            for branch in node.orelse:
                yield from import_nodes(ast.Module([branch], []), at_import_only=True)
        else:
            yield from import_nodes(node, at_import_only=at_import_only)


@functools.cache
def parsed(path: Path) -> ast.Module:
    """The syntax tree of the file at ``path``, read once per process (the suite's tests of imports share it)."""
    return ast.parse(path.read_text(encoding='utf-8'))


def imported_modules(
    source: str | ast.Module, name: str, is_package: bool, known: Mapping[str, object], *, at_import_only: bool = False
) -> tuple[set[str], set[str]]:
    """What the source (or syntax tree) of module ``name`` imports: the modules of ``known`` (``from a.b import c``: ``a.b.c`` when
    that is one, else ``a.b``), and the top-level names of every other absolute import (``numpy``, ``os``)."""
    package = name if is_package else name.rpartition('.')[0]
    ours: set[str] = set()
    others: set[str] = set()
    tree = ast.parse(source) if isinstance(source, str) else source
    for node in import_nodes(tree, at_import_only=at_import_only):
        if isinstance(node, ast.Import):
            ours.update(alias.name for alias in node.names if alias.name in known)
            others.update(alias.name.split('.')[0] for alias in node.names if alias.name not in known)
            continue
        base = node.module or ''
        if node.level:
            parts = package.split('.')
            base = '.'.join(parts[: len(parts) - node.level + 1] + ([node.module] if node.module else []))
        for alias in node.names:
            full = f'{base}.{alias.name}'
            if full in known:
                ours.add(full)
            elif base in known:
                ours.add(base)
            elif not node.level and base.split('.')[0] not in {p.split('.')[0] for p in known}:
                others.add(base.split('.')[0])
    ours.discard(name)
    return ours, others


def import_graph(
    root: Path, packages: tuple[str, ...] = PACKAGES, *, at_import_only: bool = False
) -> dict[str, tuple[set[str], set[str]]]:
    """Module -> (the modules of ``packages`` it imports, the other top-level names it imports)."""
    known = module_files(root, packages)
    return {
        name: imported_modules(parsed(path), name, is_package, known, at_import_only=at_import_only)
        for name, (path, is_package) in known.items()
    }
