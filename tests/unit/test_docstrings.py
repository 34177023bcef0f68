"""Docstrings are markdown, what the API pages (mkdocstrings) render: no Sphinx roles (``:func:`name```), which
would show as literal text. The modules and functions the submission builder inlines verbatim keep theirs (editing them would
change the committed submissions); the docs' Griffe extension turns those into code spans on the page."""

from __future__ import annotations

import importlib
import importlib.util
import inspect
import re
from pathlib import Path
from types import ModuleType

from submission import runtime

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ('vtube', 'vtube_planning', 'unicycle_mapping', 'robotarium_exp', 'submission')
ROLE = re.compile(r':(?:py:)?(?:func|class|meth|mod|attr|data|exc|obj|const|ref):`')


def griffe_roles() -> ModuleType:
    """The docs' Griffe extension (docs/hooks/griffe_roles.py), which is no package module."""
    spec = importlib.util.spec_from_file_location('griffe_roles', ROOT / 'docs' / 'hooks' / 'griffe_roles.py')
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix('').parts
    return '.'.join(parts[:-1] if parts[-1] == '__init__' else parts)


def inlined_lines(module: str) -> set[int]:
    """The source lines of the functions of ``module`` that the builder inlines (``runtime.INLINED_FUNCTIONS``)."""
    lines: set[int] = set()
    for name, functions in runtime.INLINED_FUNCTIONS:
        if name == module:
            for function in functions:
                source, first = inspect.getsourcelines(getattr(importlib.import_module(name), function))
                lines.update(range(first, first + len(source)))
    return lines


def roles_in_sources() -> list[str]:
    """``path:line: text`` of every line with a Sphinx role, outside the verbatim modules."""
    verbatim = griffe_roles().is_verbatim
    found = []
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob('*.py')):
            if verbatim(module_name(path)):
                continue
            for number, line in enumerate(path.read_text(encoding='utf-8').splitlines(), 1):
                if ROLE.search(line) and number not in inlined_lines(module_name(path)):
                    found.append(f'{path.relative_to(ROOT)}:{number}: {line.strip()}')
    return found


def test_no_docstring_uses_a_sphinx_role() -> None:
    found = roles_in_sources()
    assert not found, 'write `name` or [`name`][dotted.path] instead:\n' + '\n'.join(found)


def test_the_role_pattern_finds_roles() -> None:
    assert ROLE.search('see :func:`plan_convex`') and ROLE.search(':class:`~a.B`') and ROLE.search(':py:meth:`x`')
    assert not ROLE.search('see `plan_convex` or [`Plan`][vtube_planning.planning.plan.Plan]')


def test_every_inlined_module_is_verbatim_for_the_docs() -> None:
    verbatim = griffe_roles().is_verbatim
    assert all(verbatim(name) for name in runtime.INLINED_MODULES)
    assert verbatim('vtube_planning.onboard') and not verbatim('vtube_planning.onboarding')
    assert not verbatim('robotarium_exp.flights') and not verbatim('vtube_planning.planning.plan')


def test_the_extension_turns_roles_into_code_spans() -> None:
    hooks = griffe_roles()
    text = 'The :class:`~vtube_planning.onboard.tube.StepTube` or :meth:`project` of :mod:`.rps`.'
    assert hooks.markdown(text) == 'The `StepTube` or `project` of `rps`.'


def test_the_extension_heads_prose_after_a_section() -> None:
    hooks = griffe_roles()
    text = 'Summary.\n\nParameters\n----------\nn\n    Swarm size.\n\nWith a plan the step acts on it, always.'
    assert hooks.prose_after_sections(text).endswith('\n\nNotes\n-----\nWith a plan the step acts on it, always.')
    assert hooks.prose_after_sections('Summary.\n\nWith a plan the step acts on it, always.').count('Notes') == 0
