"""One period of the flight and the loop around it, on the trapezoid scene's flight data, against a fake Robotarium
(an exact unicycle integrator that records what it is sent) and a few steps on our V2 simulator."""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from robotarium_exp.experiment import ExperimentConfig, flight_data
from robotarium_exp.flight import Flight, Period, build_flight, flight_start, fly, robotarium_steps
from robotarium_exp.flight_data import FlightData
from robotarium_exp.rps.robotarium import Robotarium
from robotarium_exp.safety import SafetyFilter
from unicycle_mapping.mapping import si_to_uni, uni_to_si, uni_to_si_states
from unicycle_mapping.unicycle import unicycle_step
from unicycle_mapping.wheels import scale_to_wheel_limits, wheel_speeds

DT = 0.033


@pytest.fixture(scope='module')
def data(trapezoid) -> FlightData:
    scene, plan = trapezoid
    return flight_data(scene, plan, ExperimentConfig())


class FakeRobotarium:
    """Integrates the commands it is sent exactly; records every call."""

    def __init__(self, poses: np.ndarray) -> None:
        self.poses = np.array(poses, dtype=float)
        self.sent: list[tuple[np.ndarray, np.ndarray]] = []
        self.steps = 0
        self.handed: list[np.ndarray] = []

    def get_poses(self) -> np.ndarray:
        self.handed.append(self.poses.copy())
        return self.poses.copy()

    def set_velocities(self, ids: np.ndarray, velocities: np.ndarray) -> None:
        self.sent.append((np.array(ids), np.array(velocities)))

    def step(self) -> None:
        self.poses = unicycle_step(self.poses, self.sent[-1][1], DT)
        self.steps += 1


def test_one_period_maps_filters_and_bands_the_commands(data) -> None:
    flight = build_flight(data)
    poses = np.array(data.initial_conditions)
    period = flight(poses, DT)
    assert isinstance(period, Period) and isinstance(flight.safety, SafetyFilter)
    np.testing.assert_allclose(period.points_m, uni_to_si_states(poses, data.projection_distance_m))
    np.testing.assert_array_equal(period.flying, ~period.step.parked)
    assert period.flying.all() and period.band_held and not period.step.done  # at the entrance: all fly
    p = data.step
    v = period.dxu[0]
    assert np.all(v >= p.v_min_mps * (1 - 1e-9)) and np.all(v <= p.v_max_mps * (1 + 1e-9))
    assert np.abs(wheel_speeds(period.dxu, data.wheels.base_length_m, data.wheels.wheel_radius_m)).max() <= (
        data.wheels.max_wheel_speed_radps * (1 + 1e-9)
    )
    # the filter's band rows keep the speed-constrained map exact: the control points move at the safe velocity
    np.testing.assert_allclose(uni_to_si(period.dxu, poses, data.projection_distance_m), period.safe_mps, atol=1e-9)
    change = period.safe_mps - period.step.velocity
    np.testing.assert_allclose(period.barrier_correction_mps, np.hypot(change[0], change[1]))
    assert flight.safety.stats.solves == 1


def test_a_delay_compensation_predicts_from_the_filtered_velocity(data) -> None:
    """With a delay to compensate, the next period acts on the control points moved by what the robots were sent
    (the safety filter's velocity), not by the swarm step's own command."""
    from vtube_planning.onboard.delay import CommandPredictor

    compensating = replace(data, step=replace(data.step, compensate_delay_steps=2.0, compensate_lag_s=0.0))
    flight = build_flight(compensating)
    poses = np.array(data.initial_conditions)
    first = flight(poses, DT)
    assert np.abs(first.safe_mps - first.step.velocity).max() > 0.01  # the filter changed the command (from rest)
    oracle = CommandPredictor(data.n_robots, 2.0, 0.0, DT)
    oracle.sent(first.safe_mps)
    second = flight(poses, DT)
    points = uni_to_si_states(poses, data.projection_distance_m)
    expected = oracle.predict(points)
    assert np.abs(expected - points).max() > 1e-3  # the prediction moved them
    np.testing.assert_allclose(second.step.projection.l_m, flight.stepper.tube.project(expected).l_m, atol=1e-12)


def test_without_a_filter_the_exact_map_and_uniform_wheel_scaling(data) -> None:
    unsafe = build_flight(replace(data, safety=None))
    assert unsafe.safety is None
    poses = np.array(data.initial_conditions)
    period = unsafe(poses, DT)
    np.testing.assert_array_equal(period.safe_mps, period.step.velocity)
    w = data.wheels
    expected, _ = scale_to_wheel_limits(
        si_to_uni(period.step.velocity, poses, data.projection_distance_m),
        w.base_length_m,
        w.wheel_radius_m,
        w.max_wheel_speed_radps,
    )
    np.testing.assert_allclose(period.dxu, expected)
    assert period.band_held and np.all(period.barrier_correction_mps == 0.0)


def test_the_flight_carries_the_data_s_numbers(data) -> None:
    flight = build_flight(data)
    assert isinstance(flight, Flight) and flight.d == data.projection_distance_m and flight.wheels == data.wheels
    assert flight.stepper.r_a.size == data.n_robots
    s = flight.safety
    assert s is not None and s.v_min == data.step.v_min_mps and s.v_max == data.step.v_max_mps
    assert s.barrier.safety_radius == data.safety.safety_radius_m and s.barrier.boundary == data.safety.arena_m
    assert s.wheel == pytest.approx(data.wheels.rim_speed_mps)


def test_the_loop_sends_each_period_s_commands_then_steps(data) -> None:
    flight = build_flight(data)
    fake = FakeRobotarium(data.initial_conditions)
    seen: list[tuple[int, Period]] = []
    completed, periods = fly(fake, flight, DT, 4, lambda k, period: seen.append((k, period)))
    assert (completed, periods) == (False, 4) and fake.steps == 4
    assert [k for k, _ in seen] == [0, 1, 2, 3]
    for (ids, sent), (_, period), handed in zip(fake.sent, seen, fake.handed, strict=True):
        np.testing.assert_array_equal(ids, np.arange(data.n_robots))
        np.testing.assert_array_equal(sent, period.dxu)  # what the period computed, unchanged
        np.testing.assert_array_equal(period.poses, handed)  # computed from the poses handed out
    np.testing.assert_allclose(seen[1][1].poses, unicycle_step(seen[0][1].poses, seen[0][1].dxu, DT))
    assert flight.safety is not None and flight.safety.stats.solves == 4


def test_the_loop_stops_when_the_swarm_is_done_without_sending_that_period() -> None:
    """A stand-in flight that reports done at its third period: the loop returns (True, 3), two commands sent."""

    class Scripted:
        stepper = SimpleNamespace(r_a=np.zeros(2))

        def __init__(self) -> None:
            self.calls = 0

        def __call__(self, poses: np.ndarray, dt_s: float) -> SimpleNamespace:
            self.calls += 1
            return SimpleNamespace(step=SimpleNamespace(done=self.calls == 3), dxu=np.full((2, 2), 0.01 * self.calls))

    fake = FakeRobotarium(np.zeros((3, 2)))
    recorded: list[int] = []
    completed, periods = fly(fake, Scripted(), DT, 10, lambda k, _period: recorded.append(k))  # type: ignore[arg-type]
    assert (completed, periods) == (True, 3) and recorded == [0, 1, 2]
    assert fake.steps == 2 and [float(v[0, 0]) for _, v in fake.sent] == [0.01, 0.02]


def at_initial_conditions(data) -> Robotarium:
    """Our simulator with the flight's robots already at its initial conditions (no initialization)."""
    return Robotarium(
        number_of_robots=data.n_robots,
        show_figure=False,
        sim_in_real_time=False,
        initial_conditions=np.array(data.initial_conditions),
        skip_initialization=True,
    )


def test_a_few_steps_on_our_simulator_are_clean(data) -> None:
    r = at_initial_conditions(data)
    flight = build_flight(data)
    seen: list[Period] = []
    completed, periods = fly(r, flight, r.TIME_STEP, 3, lambda _k, period: seen.append(period))
    assert (completed, periods) == (False, 3) and r.iterations == 3
    before = seen[0].poses
    np.testing.assert_allclose(before, data.initial_conditions)  # no initialization: the robots start there
    assert r.errors.get('robots_too_close', 0) == 0 and r.errors.get('exceeded_actuator_limits', 0) == 0
    assert np.all(np.hypot(*(r.get_poses()[:2] - before[:2])) > 0)  # every robot moved


def test_the_flight_s_start_is_the_robotarium_s_step_count_in_any_generation(data) -> None:
    assert robotarium_steps(SimpleNamespace(iterations=7, _iteration=3)) == 7  # ours
    assert robotarium_steps(SimpleNamespace(_iterations=5)) == 5  # PyPI's V2, classic
    assert robotarium_steps(object()) == 0  # a Robotarium that does not say
    r = at_initial_conditions(data)
    assert flight_start(r, r.TIME_STEP) == {'iteration': 0, 'robotarium_time_s': 0.0, 't_s': 0.0}
    fly(r, build_flight(data), r.TIME_STEP, 2, lambda _k, _period: None)
    assert flight_start(r, 0.033) == {'iteration': 2, 'robotarium_time_s': 0.066, 't_s': 0.0}
