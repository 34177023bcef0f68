"""The geometry package's exports: every name is the object of the module that defines it."""

from __future__ import annotations

import importlib

import pytest

import vtube_planning.geometry as package


@pytest.mark.parametrize('name', getattr(package, '__all__', []))
def test_each_export_is_the_defining_object(name: str) -> None:
    value = getattr(package, name)
    home = value.__module__
    assert home.startswith('vtube_planning.') and home != package.__name__
    assert getattr(importlib.import_module(home), name) is value and name in dir(package)
