"""The package's curated exports: every name is the object of the module that defines it; the version is the
installed distribution's."""

from __future__ import annotations

import importlib
from importlib.metadata import version

import pytest

import vtube_planning


def defining_module(value: object, name: str) -> str:
    home = getattr(value, '__module__', None)
    assert home is not None and home.startswith('vtube_planning'), name
    return home


@pytest.mark.parametrize('name', [n for n in vtube_planning.__all__ if n != '__version__'])
def test_each_export_is_the_defining_object(name: str) -> None:
    value = getattr(vtube_planning, name)
    home = defining_module(value, name)
    assert home != 'vtube_planning' and getattr(importlib.import_module(home), name) is value
    assert name in dir(vtube_planning)


def test_the_version_is_the_distributions_and_unknown_names_are_named() -> None:
    assert vtube_planning.__version__ == version('vtube')
    with pytest.raises(AttributeError, match="module 'vtube_planning' has no attribute 'plan_it'"):
        vtube_planning.plan_it  # noqa: B018
