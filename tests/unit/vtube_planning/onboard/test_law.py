"""The law (s1): its terms by hand for two and three robots, one evaluation against separate ones, the speed band."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from tests.support.oracles import sigma_published
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.onboard.law import Command, interaction_gains, velocity_command
from vtube_planning.onboard.scalar import barrier_gain, sigma
from vtube_planning.params import ControlParams, SwarmParams

SWARM = SwarmParams()  # r_s = 0.4, r_a = 0.8, v in [2, 5]
PRACTICAL = ControlParams(law='practical', avoidance_gain=2.0, keeping_gain=3.0)


def command_at(
    positions: np.ndarray, r_a: np.ndarray, forward: np.ndarray, tube: VirtualTube, control: ControlParams
) -> Command:
    """The law at positions with the exact projection."""
    return velocity_command(positions, r_a, forward, tube.project(positions), control.step_params(SWARM))


def wide_tube(half_width_m: float = 10.0) -> VirtualTube:
    return VirtualTube(ArcPath((ArcPiece(50.0),)), WidthProfile(half_width_m, (WidthPart('constant', 50.0),)))


@pytest.mark.parametrize('law', ['barrier', 'practical'])
def test_one_evaluation_of_the_law_gives_the_bits_of_separate_ones(law: str) -> None:
    """Pairs (offset and d1 = 2 r_s, the avoidance gain) and walls (r_s, the keeping gain) in one call of the law,
    element by element: exactly what each kind gives alone with scalar parameters (the simulator's runs depend on
    these bits); with no pairs or no walls, the other kind alone."""
    params = replace(PRACTICAL, law=law).step_params(SWARM)
    r_s = params.r_s_m
    rng = np.random.default_rng(7)
    dist = rng.uniform(0.5, 1.6, 40)  # inside the safety distance 2 r_s, the band and beyond
    band = r_s + rng.uniform(0.8, 1.2, 40)
    clearance = rng.uniform(-0.1, 1.0, 12)
    r_a = rng.uniform(0.8, 1.2, 12)
    if law == 'barrier':
        pairs = barrier_gain(dist, 2 * r_s, 2 * r_s, band, params.avoidance_gain)
        walls = barrier_gain(clearance, r_s, r_s, r_a, params.keeping_gain)
    else:
        pairs = params.avoidance_gain * sigma(dist, 2 * r_s, band)[0]
        walls = params.keeping_gain * sigma(clearance, r_s, r_a)[0]
    assert np.count_nonzero(pairs) > 10 and np.count_nonzero(walls) > 3  # both kinds push
    together = interaction_gains(dist, band, clearance, r_a, params)
    np.testing.assert_array_equal(together[0], pairs)
    np.testing.assert_array_equal(together[1], walls)
    none = np.empty(0)
    np.testing.assert_array_equal(interaction_gains(dist, band, none, none, params)[0], pairs)
    np.testing.assert_array_equal(interaction_gains(none, none, clearance, r_a, params)[1], walls)


# ---------------------------------------------------------------------- the law, by hand


def test_two_robots_practical_law_by_hand() -> None:
    tube = wide_tube()
    positions = np.array([[10.0, 11.0], [0.0, 0.0]])  # 1 m apart along the tube, on the centre line
    command = command_at(positions, np.full(2, 0.8), np.full(2, 3.0), tube, PRACTICAL)
    push = 2.0 * 0.5  # k_m sigma(1.0; 0.8, 1.2): the middle of the band
    np.testing.assert_allclose(command.avoidance.T, [[-push, 0.0], [push, 0.0]], atol=1e-12)
    np.testing.assert_allclose(command.tube_keeping, 0.0, atol=1e-12)  # 10 m from both walls
    np.testing.assert_allclose(command.velocity.T, [[3.0 - push, 0.0], [3.0 + push, 0.0]], atol=1e-12)


@pytest.mark.parametrize('law', ['practical', 'barrier'])
def test_a_lone_robot_is_pushed_by_no_one(law: str) -> None:
    """One robot: no pairs, no avoidance; near a wall it is still kept in (a swarm of one flies on the Robotarium)."""
    tube = wide_tube(2.0)
    command = command_at(np.array([[5.0], [1.4]]), np.full(1, 0.8), np.full(1, 3.0), tube, ControlParams(law=law))
    np.testing.assert_array_equal(command.avoidance, 0.0)
    assert command.tube_keeping[1, 0] < 0.0 and command.velocity.shape == (2, 1)


def test_three_robots_sum_their_pushes_and_use_their_own_radius() -> None:
    tube = wide_tube()
    positions = np.array([[10.0, 11.0, 10.0], [0.0, 0.0, 0.9]])
    r_a = np.array([0.8, 0.8, 0.3 + 0.4])  # the third robot's band ends at r_s + r_a = 1.1 m
    command = command_at(positions, r_a, np.full(3, 3.0), tube, PRACTICAL)
    s_10 = sigma_published(1.0, 0.8, 1.2)
    s_09 = sigma_published(0.9, 0.8, 1.2)
    d = math.hypot(1.0, 0.9)  # robots 2 and 3
    s_23 = sigma_published(d, 0.8, 1.2)  # zero: 1.345 m is beyond the band of robots 1 and 2
    expected_0 = 2.0 * (s_10 * np.array([-1.0, 0.0]) + s_09 * np.array([0.0, -1.0]))
    expected_1 = 2.0 * (s_10 * np.array([1.0, 0.0]) + s_23 * np.array([1.0, -0.9]) / d)
    expected_2 = 2.0 * sigma_published(0.9, 0.8, 1.1) * np.array([0.0, 1.0])  # its own, narrower band
    np.testing.assert_allclose(command.avoidance.T, [expected_0, expected_1, expected_2], atol=1e-12)


def test_tube_keeping_pushes_towards_the_centre_line() -> None:
    tube = wide_tube(2.0)
    positions = np.array([[5.0, 5.0, 5.0], [1.4, -1.4, 0.0]])  # 0.6 m from the left / right wall, centre
    command = command_at(positions, np.full(3, 0.8), np.full(3, 3.0), tube, PRACTICAL)
    push = 3.0 * sigma_published(0.6, 0.4, 0.8)
    np.testing.assert_allclose(command.tube_keeping.T, [[0.0, -push], [0.0, push], [0.0, 0.0]], atol=1e-12)


def test_commands_always_lie_in_the_speed_band() -> None:
    rng = np.random.default_rng(0)
    tube = wide_tube(3.0)
    for law in ('practical', 'barrier'):
        positions = np.vstack([rng.uniform(0, 20, 300), rng.uniform(-3.5, 3.5, 300)])
        command = command_at(
            positions, rng.uniform(0.8, 2.0, 300), rng.uniform(2, 5, 300), tube, ControlParams(law=law)
        )
        speed = np.hypot(*command.velocity)
        assert np.all(speed >= 2.0 - 1e-9) and np.all(speed <= 5.0 + 1e-9)


def test_the_forward_progress_form_never_reverses_and_stays_in_the_band() -> None:
    """Random crowds: forward component >= v_min, speed <= v_max; where the pushes fit the room v* - v_min the
    command is v* t_c plus the pushes unchanged; where the paper's radial sat would send a robot backwards, it does
    not."""
    rng = np.random.default_rng(7)
    tube = wide_tube(3.0)
    forward_law = ControlParams(saturation='forward')
    positions = np.vstack([rng.uniform(0, 20, 300), rng.uniform(-3.5, 3.5, 300)])
    r_a, v_star = rng.uniform(0.8, 2.0, 300), rng.uniform(2, 5, 300)
    command = command_at(positions, r_a, v_star, tube, forward_law)
    tangent = tube.project(positions).tangent
    along = np.einsum('ij,ij->j', command.velocity, tangent)
    assert np.all(along >= 2.0 - 1e-9) and np.all(np.hypot(*command.velocity) <= 5.0 + 1e-9)
    gentle = command_at(
        positions,
        r_a,
        v_star,
        tube,
        ControlParams(law='practical', saturation='forward', avoidance_gain=0.2, keeping_gain=0.2),
    )
    pushes = gentle.avoidance + gentle.tube_keeping
    small = (np.hypot(*pushes) <= v_star - 2.0) & (np.hypot(*(gentle.forward + pushes)) <= 5.0)
    assert small.sum() > 20
    np.testing.assert_allclose(gentle.velocity[:, small], (gentle.forward + pushes)[:, small], atol=1e-12)
    radial = command_at(positions, r_a, v_star, tube, ControlParams())
    backwards = np.einsum('ij,ij->j', radial.velocity, tangent) < 0
    assert backwards.sum() > 5  # the crowd is tight enough for the radial sat to reverse some robots
