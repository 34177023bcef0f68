"""The analysis package's lazy exports are the defining objects."""

from __future__ import annotations

import importlib

import pytest

import robotarium_exp.analysis


@pytest.mark.parametrize('name', robotarium_exp.analysis.__all__)
def test_each_export_is_its_module_s_object(name: str) -> None:
    exported = getattr(robotarium_exp.analysis, name)
    home = next(
        m
        for m in ('bags', 'loaders', 'matfiles', 'metrics', 'report', 'trajectory')
        if hasattr(importlib.import_module(f'robotarium_exp.analysis.{m}'), name)
    )
    assert exported is getattr(importlib.import_module(f'robotarium_exp.analysis.{home}'), name)
    assert name in dir(robotarium_exp.analysis)


def test_an_unknown_name_is_an_attribute_error() -> None:
    with pytest.raises(AttributeError):
        robotarium_exp.analysis.not_an_export  # noqa: B018
