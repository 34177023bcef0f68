"""FlightData: what a submission file embeds."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.experiment import (
    ExperimentConfig,
    flight_data,
)
from robotarium_exp.flight_data import FlightData
from vtube_planning import load_scene
from vtube_planning.planning.planner import plan_convex


def test_flight_data_is_what_a_file_embeds() -> None:
    """Rounded once: its plain literal reads back to the same literal; without planning it carries no plan."""
    scene = load_scene('robotarium_trapezoid')
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    data = flight_data(scene, plan, ExperimentConfig())
    plain = data.to_plain()
    assert FlightData.from_plain(plain).to_plain() == plain and data.planned
    assert plain['tube_hash'] == scene.tube.fingerprint() and plain['scene'] == scene.name
    assert data.plan is not None and np.array_equal(data.plan.l_m, np.array([float(f'{v:.6g}') for v in plan.l_m]))
    unplanned = flight_data(scene, plan, ExperimentConfig(planning=False))
    assert unplanned.plan is None and not unplanned.planned
    with pytest.raises(ValueError, match=r"missing \['max_steps'\], unexpected \['steps'\]"):
        FlightData.from_plain({('steps' if k == 'max_steps' else k): v for k, v in plain.items()})
