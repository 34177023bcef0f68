"""The package's lazy exports are the defining objects; its exceptions' hierarchy."""

from __future__ import annotations

import importlib

import pytest

import robotarium_exp
from robotarium_exp.errors import AnalysisError, ExperimentError, RobotariumExpError, SpecError
from robotarium_exp.rps.errors import RobotariumError

HOMES = ('errors', 'rps.errors', 'experiment', 'spec')


@pytest.mark.parametrize('name', robotarium_exp.__all__)
def test_each_export_is_its_module_s_object(name: str) -> None:
    homes = [m for m in HOMES if name in vars(importlib.import_module(f'robotarium_exp.{m}'))]
    assert homes, f'{name} is defined in none of {HOMES}'
    assert getattr(robotarium_exp, name) is getattr(importlib.import_module(f'robotarium_exp.{homes[0]}'), name)
    assert name in dir(robotarium_exp)


def test_the_errors_are_value_errors_under_one_base_and_rps_raises_assertion_errors() -> None:
    for error in (SpecError, ExperimentError, AnalysisError):
        assert issubclass(error, RobotariumExpError) and issubclass(error, ValueError)
    assert issubclass(RobotariumError, AssertionError) and not issubclass(RobotariumError, RobotariumExpError)
    with pytest.raises(AttributeError):
        robotarium_exp.not_an_export  # noqa: B018
