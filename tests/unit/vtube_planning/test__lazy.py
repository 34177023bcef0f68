"""lazy_exports: a name is imported from its module on first use, then kept; unknown names are named."""

from __future__ import annotations

import sys
import types

import pytest

from vtube_planning._lazy import lazy_exports


@pytest.fixture
def package(monkeypatch):
    """A package ``fakepkg`` whose ``sqrt`` and ``pi`` come from ``math``, ``dumps`` from ``json``."""
    module = types.ModuleType('fakepkg')
    module.__getattr__, module.__dir__ = lazy_exports('fakepkg', {'math': ('sqrt', 'pi'), 'json': ('dumps',)})
    module.own = 1
    monkeypatch.setitem(sys.modules, 'fakepkg', module)
    return module


def test_names_come_from_their_modules_and_are_kept(package) -> None:
    import json
    import math

    assert 'sqrt' not in vars(package)
    assert package.sqrt is math.sqrt and package.pi == math.pi and package.dumps is json.dumps
    assert vars(package)['sqrt'] is math.sqrt  # set on the module: the next lookup does not come back


def test_dir_lists_own_and_lazy_names_sorted(package) -> None:
    names = dir(package)
    assert names == sorted(names) and {'own', 'sqrt', 'pi', 'dumps'} <= set(names)


def test_an_unknown_name_raises_attribute_error_naming_it(package) -> None:
    with pytest.raises(AttributeError, match="module 'fakepkg' has no attribute 'cos'"):
        package.cos  # noqa: B018
    assert not hasattr(package, 'nothing')
