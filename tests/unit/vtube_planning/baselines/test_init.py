"""The baselines package: its two modules, the optimized flocking and the distributed NMPC of the paper."""

from __future__ import annotations

import pkgutil

from vtube_planning import baselines


def test_the_package_holds_the_flocking_and_the_nmpc_baselines() -> None:
    assert {m.name for m in pkgutil.iter_modules(baselines.__path__)} == {'flocking', 'nmpc'}
    assert 'flocking' in baselines.__doc__ and 'NMPC' in baselines.__doc__
