"""The rooms of vtube_planning (the studies, the tubes from maps): each one's docstring names its modules in the
order of its import contract."""

from __future__ import annotations

import pkgutil
import re
import sys
from pathlib import Path
from types import ModuleType

import pytest

import vtube_planning.geometry.from_maps
import vtube_planning.studies

if sys.version_info >= (3, 11):
    import tomllib
else:
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[3]


def named_in_order(doc: str) -> list[str]:
    """The module names a room's docstring quotes (````name````), in order, once each."""
    return list(dict.fromkeys(re.findall(r'``([a-z_]+)``', doc)))


def contract_order(container: str) -> list[str]:
    """The modules of ``container``'s layers contract, from the top layer down."""
    contracts = tomllib.loads((ROOT / 'pyproject.toml').read_text(encoding='utf-8'))['tool']['importlinter']
    (layers,) = [c['layers'] for c in contracts['contracts'] if c.get('containers') == [container]]
    return [name.strip() for layer in layers for name in layer.split(':')]


@pytest.mark.parametrize('room', [vtube_planning.studies, vtube_planning.geometry.from_maps], ids=lambda m: m.__name__)
def test_the_docstring_names_every_module_in_the_contracts_order(room: ModuleType) -> None:
    modules = {info.name for info in pkgutil.iter_modules(room.__path__)}
    named = [name for name in named_in_order(room.__doc__ or '') if name in modules]
    assert set(named) == modules
    assert named == contract_order(room.__name__)


def test_named_in_order_keeps_the_first_mention() -> None:
    assert named_in_order('``b`` then ``a`` and ``b``') == ['b', 'a']
