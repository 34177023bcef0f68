"""The classic ``rps`` package mirrors the classic layout; where it computes what V2 does it reuses V2's code."""

from __future__ import annotations

import importlib

import robotarium_exp.rps_classic
import robotarium_exp.rps_classic.utilities
from robotarium_exp.rps_import import CLASSIC


def test_every_classic_module_is_there_under_its_name() -> None:
    for suffix in CLASSIC.modules:
        module = importlib.import_module('robotarium_exp.rps_classic' + suffix)
        assert module.__name__ == 'robotarium_exp.rps_classic' + suffix
    assert '.utilities.barrier_certificates2' in CLASSIC.modules and '.examples' not in CLASSIC.modules
    assert robotarium_exp.rps_classic.utilities.__name__.endswith('rps_classic.utilities')
