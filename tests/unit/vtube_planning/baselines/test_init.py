"""The baselines package: its two modules, the optimized flocking and the distributed NMPC of the paper."""

from __future__ import annotations

import pkgutil

import vtube_planning.baselines as package


def test_the_package_holds_the_flocking_and_the_nmpc_baselines() -> None:
    assert {m.name for m in pkgutil.iter_modules(package.__path__)} == {'flocking', 'nmpc'}
    assert 'flocking' in package.__doc__ and 'NMPC' in package.__doc__
