"""Every public function and class of the curated API (the ``__all__`` of the packages and of the subpackages that
export names) has an entry on an API reference page (docs/api/*.md, a ``::: dotted.path`` of mkdocstrings)."""

from __future__ import annotations

import importlib
import inspect
import re
import textwrap
from pathlib import Path
from types import ModuleType

import yaml

ROOT = Path(__file__).resolve().parents[2]
CURATED = (
    'vtube',
    'vtube.cli',
    'vtube_planning',
    'vtube_planning.geometry',
    'vtube_planning.planning',
    'vtube_planning.swarm',
    'vtube_planning.baselines',
    'vtube_planning.onboard',
    'unicycle_mapping',
    'robotarium_exp',
    'robotarium_exp.analysis',
    'submission',
)
"""The packages whose ``__all__`` is the API the reference pages document."""
DIRECTIVE = re.compile(r'^::: (\S+)\n((?:    .*\n)*)', re.MULTILINE)


def resolve(path: str) -> object:
    """The object at a dotted path: the longest importable module, then attributes."""
    parts = path.split('.')
    for k in range(len(parts), 0, -1):
        try:
            found: object = importlib.import_module('.'.join(parts[:k]))
        except ImportError:
            continue
        for part in parts[k:]:
            found = getattr(found, part)
        return found
    raise ImportError(path)


def documented(page: str) -> list[object]:
    """What a page's directives render: an object, or a module's members (all public ones it defines, the listed
    ones, or none with ``members: false``)."""
    rendered: list[object] = []
    for match in DIRECTIVE.finditer(page):
        options = (yaml.safe_load(textwrap.dedent(match.group(2))) or {}).get('options') or {}
        target = resolve(match.group(1))
        if not isinstance(target, ModuleType):
            rendered.append(target)
            continue
        members = options.get('members')
        if members is False:
            continue
        if isinstance(members, list):
            rendered.extend(getattr(target, name) for name in members)
        else:
            rendered.extend(
                value
                for name, value in vars(target).items()
                if not name.startswith('_') and getattr(value, '__module__', None) == target.__name__
            )
    return rendered


def missing_entries(pages: list[str]) -> list[str]:
    """``package.name`` of every exported function or class that no page renders."""
    rendered = {id(value) for page in pages for value in documented(page)}
    missing = []
    for package in CURATED:
        module = importlib.import_module(package)
        for name in module.__all__:
            value = getattr(module, name)
            if (inspect.isclass(value) or inspect.isfunction(value)) and id(value) not in rendered:
                missing.append(f'{package}.{name} ({value.__module__}.{value.__qualname__})')
    return missing


def api_pages() -> list[str]:
    return [path.read_text(encoding='utf-8') for path in sorted((ROOT / 'docs' / 'api').glob('*.md'))]


def test_every_exported_function_and_class_has_a_reference_entry() -> None:
    missing = missing_entries(api_pages())
    assert not missing, 'add a ::: entry to a page of docs/api for:\n' + '\n'.join(missing)


def test_a_page_without_an_entry_is_reported() -> None:
    pages = [page.replace('::: vtube_planning.planning.planner.plan_convex\n', '') for page in api_pages()]
    missing = missing_entries(pages)
    assert 'vtube_planning.plan_convex (vtube_planning.planning.planner.plan_convex)' in missing
    assert 'vtube_planning.planning.plan_convex (vtube_planning.planning.planner.plan_convex)' in missing


def test_a_module_entry_renders_its_members_as_its_options_say() -> None:
    from unicycle_mapping import si_to_uni, wheel_speeds
    from vtube_planning.errors import PlanError

    listed = '::: unicycle_mapping\n    options:\n      members:\n        - si_to_uni\n'
    assert documented(listed) == [si_to_uni]
    assert documented('::: unicycle_mapping\n    options:\n      members: false\n') == []
    assert PlanError in documented('::: vtube_planning.errors\n')
    assert wheel_speeds not in documented(listed)


def test_every_reference_page_is_in_the_nav() -> None:
    nav = (ROOT / 'mkdocs.yml').read_text(encoding='utf-8')
    for path in (ROOT / 'docs' / 'api').glob('*.md'):
        assert f'api/{path.name}' in nav, path.name
