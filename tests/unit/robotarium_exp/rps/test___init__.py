"""The V2 ``rps`` package mirrors rps's layout: its modules import under the same names."""

from __future__ import annotations

import importlib

import robotarium_exp.rps
import robotarium_exp.rps.utilities
from robotarium_exp.rps_import import V2


def test_every_rps_module_is_there_under_its_name() -> None:
    for suffix in V2.modules:
        module = importlib.import_module('robotarium_exp.rps' + suffix)
        assert module.__name__ == 'robotarium_exp.rps' + suffix
    assert robotarium_exp.rps.utilities.__name__ == 'robotarium_exp.rps.utilities'
    assert 'from robotarium_exp.rps.robotarium import Robotarium' in (robotarium_exp.rps.__doc__ or '')
