"""Optimized flocking's terms against values computed by hand for two robots and a wall."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vtube_planning.baselines.flocking import FlockingParams, braking_curve, flocking_command
from vtube_planning.errors import ParamsError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.params import SwarmParams

SIMPLE = FlockingParams(
    v_flock=1.0,
    v_max=10.0,
    v_min=0.0,
    r0_rep=1.0,
    p_rep=2.0,
    v_rep=5.0,
    r0_frict=0.5,
    c_frict=0.1,
    v_frict=0.2,
    p_frict=1.0,
    a_frict=1.0,
    r0_shill=0.0,
    v_shill=1.0,
    p_shill=1.0,
    a_shill=1.0,
)


def straight(half_width: float) -> VirtualTube:
    return VirtualTube(ArcPath((ArcPiece(20.0),)), WidthProfile(half_width, (WidthPart('constant', 20.0),)))


def test_braking_curve_by_hand() -> None:
    # a = 2, p = 1: linear r p below r = a / p^2 = 2, then sqrt(2 a r - a^2 / p^2); 0 for r <= 0
    np.testing.assert_allclose(
        braking_curve(np.array([-1.0, 0.0, 1.0, 2.0, 3.0]), 2.0, 1.0), [0.0, 0.0, 1.0, 2.0, math.sqrt(8.0)]
    )


def test_two_robots_repulsion_and_alignment_by_hand() -> None:
    tube = straight(10.0)  # walls 10 m away: D(10) = sqrt(19) > |v_s - v_i|, no wall term
    positions = np.array([[2.0, 2.6], [0.0, 0.0]])
    velocities = np.array([[1.0, 1.5], [0.0, 0.0]])
    command = flocking_command(positions, velocities, tube.project(positions), SIMPLE)
    repulsion = 2.0 * (1.0 - 0.6)  # p_rep (r0_rep - r) = 0.8 < v_rep
    # |v_j - v_i| = 0.5 exceeds max(v_frict, D(0.6 - 0.5)) = max(0.2, 0.1) = 0.2 by 0.3; C_frict 0.1
    alignment = 0.1 * (0.5 - 0.2)
    np.testing.assert_allclose(
        command.T, [[1.0 - repulsion + alignment, 0.0], [1.0 + repulsion - alignment, 0.0]], atol=1e-12
    )


def test_wall_shill_by_hand() -> None:
    tube = straight(1.0)
    positions = np.array([[5.0], [0.8]])  # 0.2 m from the left wall, 1.8 m from the right one
    velocities = np.array([[1.0], [0.0]])
    command = flocking_command(positions, velocities, tube.project(positions), SIMPLE)
    # left shill moves inward at (0, -1): |v_s - v_i| = sqrt(2) exceeds D(0.2) = 0.2; right: D(1.8) = 1.61 > sqrt(2)
    pull = math.sqrt(2.0) - 0.2
    expected = np.array([1.0, 0.0]) + pull * np.array([-1.0, -1.0]) / math.sqrt(2.0)
    np.testing.assert_allclose(command[:, 0], expected, atol=1e-12)


def test_speed_limits_cap_and_floor() -> None:
    tube = straight(10.0)
    positions = np.array([[2.0, 2.05], [0.0, 0.0]])  # strong repulsion: robot 0 is pushed backwards
    velocities = np.zeros((2, 2))
    free = flocking_command(positions, velocities, tube.project(positions), SIMPLE)
    constrained = flocking_command(
        positions, velocities, tube.project(positions), FlockingParams(**{**vars(SIMPLE), 'v_min': 2.0, 'v_max': 2.5})
    )
    assert free[0, 0] < 0.0  # with v_min = 0 a flocking robot may even back up
    np.testing.assert_allclose(np.hypot(*constrained), [2.0, 2.5])  # floored and capped, direction kept
    assert constrained[0, 0] < 0.0


def test_scaled_parameters_follow_the_seed_geometry() -> None:
    swarm = SwarmParams()
    scaled = FlockingParams.scaled(swarm)
    assert scaled.r0_rep == pytest.approx(swarm.r_s_m + swarm.r_a_m)  # lengths scale onto r_s + r_a
    assert scaled.v_max == swarm.v_max_mps and scaled.v_flock == pytest.approx(4.0 * 5.0 / 8.0)
    assert scaled.v_min == 0.0 and FlockingParams.scaled(swarm, speed_constrained=True).v_min == swarm.v_min_mps
    with pytest.raises(ParamsError, match='flocking parameter p_rep must be a finite number >= 0'):
        FlockingParams(**{**vars(SIMPLE), 'p_rep': -1.0})
