"""The tube experiment on both Robotarium scenes, on the bundled simulator."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.errors import ExperimentError
from robotarium_exp.experiment import (
    ExperimentConfig,
    initial_conditions,
    initializer_stall_risk,
    order_for_v2_initializer,
    parking_slots,
    run_experiment,
)
from robotarium_exp.rps.robotarium import Robotarium
from vtube_planning import load_scene


def test_initial_conditions_are_spread_for_the_testbed() -> None:
    for name in ('robotarium_trapezoid', 'robotarium_curve'):
        scene = load_scene(name)
        ic = initial_conditions(scene)
        gaps = np.hypot(*(ic[:2, :, None] - ic[:2, None, :]))[np.triu_indices(ic.shape[1], 1)]
        assert ic.shape == (3, 6) and gaps.min() >= 0.4 - 1e-12
        assert np.all(np.abs(ic[0]) <= 1.375) and np.all(np.abs(ic[1]) <= 0.875)
        assert scene.tube.project(ic[:2]).inside.all()
        slots = parking_slots(scene)
        assert np.all(np.abs(slots[0]) <= 1.5) and np.all(np.abs(slots[1]) <= 0.85)


def test_planning_without_a_plan_is_refused() -> None:
    with pytest.raises(ExperimentError, match='no plan was given'):
        run_experiment(Robotarium, load_scene('robotarium_curve'), None, ExperimentConfig())


def test_robots_zero_and_one_take_the_front_corners() -> None:
    """V2 never rescues robots 0 and 1 from a late deadlock: they get the slots with the fewest neighbours."""
    ic = initial_conditions(load_scene('robotarium_trapezoid'))
    gaps = np.hypot(*(ic[:2, :, None] - ic[:2, None, :]))
    neighbours = (gaps < 0.5).sum(axis=0) - 1
    assert neighbours[0] == neighbours[1] == neighbours.min() == 2  # corners of the 2 x 3 formation
    assert ic[0, 0] == ic[0, 1] == ic[0].max()  # both in the front row
    grid = np.array([[0.0, 0.0, 0.0, -0.4, -0.4, -0.4], [-0.4, 0.0, 0.4, -0.4, 0.0, 0.4], [0.0] * 6])
    order = order_for_v2_initializer(grid)
    assert sorted(order) == list(range(6)) and set(order[:2]) == {0, 2}
    assert initializer_stall_risk(grid[:, order]) is None
    risk = initializer_stall_risk(grid)  # robot 1 in the middle of the front row, with 3 neighbours
    assert risk is not None and risk.startswith('robots 0 and 1 start at slots with 2 and 3 neighbours within 0.50 m')
    assert 'order_for_v2_initializer' in risk
    assert initializer_stall_risk(grid[:, :2]) is None  # two robots: nothing to choose
