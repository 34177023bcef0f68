"""The curated exports of vtube_planning and of its baselines, geometry, planning and swarm packages: every name is
the object of the module that defines it; the version is the installed distribution's."""

from __future__ import annotations

import importlib
from importlib.metadata import version
from types import ModuleType

import pytest

import vtube_planning
import vtube_planning.baselines
import vtube_planning.geometry
import vtube_planning.planning
import vtube_planning.swarm

PACKAGES = (
    vtube_planning,
    vtube_planning.baselines,
    vtube_planning.geometry,
    vtube_planning.planning,
    vtube_planning.swarm,
)


@pytest.mark.parametrize(
    ('package', 'name'),
    [(p, n) for p in PACKAGES for n in getattr(p, '__all__', []) if n != '__version__'],
    ids=lambda value: value.__name__ if isinstance(value, ModuleType) else value,
)
def test_each_export_is_the_defining_object(package: ModuleType, name: str) -> None:
    value = getattr(package, name)
    home = getattr(value, '__module__', None)
    assert home is not None and home.startswith('vtube_planning.') and home != package.__name__, name
    assert getattr(importlib.import_module(home), name) is value and name in dir(package)


def test_the_version_is_the_distributions_and_unknown_names_are_named() -> None:
    assert vtube_planning.__version__ == version('vtube')
    with pytest.raises(AttributeError, match="module 'vtube_planning' has no attribute 'plan_it'"):
        vtube_planning.plan_it  # noqa: B018


def test_the_planner_and_the_simulator_are_found_where_the_docs_say() -> None:
    from vtube_planning.planning import plan_convex
    from vtube_planning.swarm.simulate import simulate

    assert 'plan_convex' in vtube_planning.planning.__all__ and plan_convex is vtube_planning.plan_convex
    assert simulate is vtube_planning.simulate and callable(vtube_planning.simulate)
    assert {'FlockingParams', 'NmpcSwarm'} <= set(vtube_planning.baselines.__all__)
