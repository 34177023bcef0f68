"""FlightData: what a submission file embeds."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.experiment import (
    ExperimentConfig,
    flight_data,
)
from robotarium_exp.flight_data import SIGNIFICANT_DIGITS, FlightData, SafetyData, Wheels, plain_value
from robotarium_exp.scene import load_scene
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


def test_plain_values_round_to_six_significant_digits_and_refuse_the_rest() -> None:
    assert plain_value(np.array([[1 / 3, 2e-9], [123456789.0, -0.5]])) == [[0.333333, 2e-09], [123457000.0, -0.5]]
    assert plain_value({'a': (1, True, None, 'x'), 2: [np.pi]}) == {'a': [1, True, None, 'x'], '2': [3.14159]}
    rng = np.random.default_rng(1)
    for value in rng.normal(0, 10.0, 200) * 10.0 ** rng.integers(-8, 8, 200):
        rounded = plain_value(float(value))
        assert isinstance(rounded, float) and rounded == float(f'{value:.6g}')
        assert abs(rounded - value) <= 5e-6 * abs(value)  # six significant digits
    with pytest.raises(ValueError, match=r'has no plain form'):
        plain_value(object())
    assert SIGNIFICANT_DIGITS == 6


def test_rounding_is_idempotent_and_the_wheels_rim_speed(trapezoid) -> None:
    scene, plan = trapezoid
    data = flight_data(scene, plan, ExperimentConfig())
    again = data.rounded()
    assert again.to_plain() == data.to_plain() and again.rounded().to_plain() == data.to_plain()
    assert data.wheels == Wheels(0.11, 0.016, 12.5) and data.wheels.rim_speed_mps == pytest.approx(0.2)
    assert data.safety == SafetyData(0.2, data.safety.barrier_gain, (-1.6, 1.6, -1.0, 1.0))
    assert data.tube.xy_m.shape == (2, data.tube.l_m.size) and data.tube_edges_m.shape[:2] == (2, 2)
    unsafe = flight_data(scene, plan, ExperimentConfig(barrier=False))
    assert unsafe.safety is None and FlightData.from_plain(unsafe.to_plain()).safety is None


def test_from_plain_names_bad_nested_keys(trapezoid) -> None:
    scene, plan = trapezoid
    plain = flight_data(scene, plan, ExperimentConfig()).to_plain()
    for key, what in (('wheels', 'wheels'), ('safety', "flight data's safety"), ('step', "flight data's step")):
        broken = dict(plain)
        broken[key] = {**plain[key], 'extra': 1}  # type: ignore[dict-item]
        with pytest.raises(ValueError, match=rf"{what}: missing \[\], unexpected \['extra'\]"):
            FlightData.from_plain(broken)
    broken = dict(plain)
    broken['tube'] = {k: v for k, v in plain['tube'].items() if k != 'area_m2'}  # type: ignore[union-attr]
    with pytest.raises(ValueError, match=r"TubeSamples: missing \['area_m2'\]"):
        FlightData.from_plain(broken)
