"""The testbed's numbers: they agree with both rps generations' constants and with each other."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import robotarium_exp.rps_classic.robotarium_abc as classic_abc
from robotarium_exp.errors import SpecError
from robotarium_exp.rps.robotarium_abc import ARENA, ARobotarium
from robotarium_exp.spec import ROBOTARIUM, RobotariumSpec


def test_the_spec_is_the_v2_simulator_s_constants() -> None:
    s = ROBOTARIUM
    assert s.time_step_s == ARobotarium.TIME_STEP == 0.033
    assert s.arena_m == ARENA == (-1.6, 1.6, -1.0, 1.0)
    np.testing.assert_array_equal(ARobotarium.BOUNDARIES, s.arena_m)
    assert (s.max_linear_speed_mps, s.wheel_radius_m, s.base_length_m) == (0.2, 0.016, 0.11)
    assert s.robot_diameter_m == ARobotarium.ROBOT_DIAMETER
    assert (s.collision_diameter_m, s.collision_offset_m) == (ARobotarium.COLLISION_DIAMETER, 0.025)
    assert s.max_wheel_speed_radps == pytest.approx(ARobotarium.MAX_WHEEL_VELOCITY) == pytest.approx(12.5)


def test_the_classic_generation_has_the_same_arena_step_and_wheel_limit() -> None:
    """Classic states the arena as [x, y, width, height] and the GTernal's linear speed limit."""
    from robotarium_exp.rps_classic.robotarium import Robotarium

    ic = np.array([[0.0, 0.5], [0.0, 0.0], [0.0, 0.0]])
    classic = Robotarium(number_of_robots=2, show_figure=False, sim_in_real_time=False, initial_conditions=ic)
    x, y, width, height = classic.boundaries
    assert (x, x + width, y, y + height) == pytest.approx(ROBOTARIUM.arena_m)
    assert classic.time_step == ROBOTARIUM.time_step_s and classic.wheel_radius == ROBOTARIUM.wheel_radius_m
    assert classic.max_linear_velocity == ROBOTARIUM.max_linear_speed_mps
    assert classic.max_wheel_velocity == pytest.approx(ROBOTARIUM.max_wheel_speed_radps)
    classic_abc.SHARED_ERRORS.clear()


def test_the_numbers_agree_with_each_other() -> None:
    s = ROBOTARIUM
    xmin, xmax, ymin, ymax = s.arena_m
    bx, by = s.ic_box_m
    assert xmin + s.arena_margin_m <= -bx < bx <= xmax - s.arena_margin_m  # initial conditions fit the arena
    assert ymin + s.arena_margin_m <= -by < by <= ymax - s.arena_margin_m
    assert s.ic_spacing_m > s.collision_diameter_m + 2 * s.collision_offset_m  # spaced ICs are never too close
    assert s.collision_diameter_m > s.robot_diameter_m  # the collision disc covers the body
    assert s.max_robots * np.pi * (s.ic_spacing_m / 2) ** 2 < (2 * bx) * (2 * by) + 4 * bx * s.ic_spacing_m
    assert s.duration_factor > 1
    # the GTernal's fastest turn on the spot: both wheels at the limit, opposite
    assert 2 * s.wheel_radius_m * s.max_wheel_speed_radps / s.base_length_m == pytest.approx(2 * 0.2 / 0.11)


def test_arena_text_and_outside_points_with_a_margin() -> None:
    assert ROBOTARIUM.arena_text == '[-1.6, 1.6] x [-1, 1]'
    points = np.array([[0.0, 1.59, 1.61, -1.58, 0.0], [0.0, 0.0, 0.0, 0.0, -0.96]])
    np.testing.assert_array_equal(ROBOTARIUM.outside_arena(points), [False, False, True, False, False])
    np.testing.assert_array_equal(ROBOTARIUM.outside_arena(points, 0.05), [False, True, True, True, True])
    rng = np.random.default_rng(0)
    random = rng.uniform(-2, 2, (2, 500))
    inside = (np.abs(random[0]) <= 1.6) & (np.abs(random[1]) <= 1.0)
    np.testing.assert_array_equal(ROBOTARIUM.outside_arena(random), ~inside)


@pytest.mark.parametrize(
    ('change', 'match'),
    [
        ({'arena_m': (1.0, -1.0, -1.0, 1.0)}, r'x_min < x_max and y_min < y_max; got \(1.0, -1.0, -1.0, 1.0\)'),
        ({'time_step_s': 0.0}, r'time_step_s must be > 0; got 0.0'),
        ({'wheel_radius_m': -0.016}, r'wheel_radius_m must be > 0'),
    ],
)
def test_a_bad_spec_is_refused_by_name(change: dict, match: str) -> None:
    with pytest.raises(SpecError, match=match):
        dataclasses.replace(ROBOTARIUM, **change)
    assert issubclass(SpecError, ValueError)


def test_a_spec_is_frozen_and_its_wheel_limit_follows_its_numbers() -> None:
    other = RobotariumSpec(max_linear_speed_mps=0.3, wheel_radius_m=0.02)
    assert other.max_wheel_speed_radps == pytest.approx(15.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        ROBOTARIUM.time_step_s = 0.1  # type: ignore[misc]
