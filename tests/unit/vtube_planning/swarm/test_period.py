"""One simulated control period: the controller or a baseline, the faults acting on the command."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.onboard.density import swarm_density
from vtube_planning.onboard.stepper import SwarmStep
from vtube_planning.params import ControlParams, SwarmParams
from vtube_planning.swarm.faults import Faults, RobotFailure
from vtube_planning.swarm.period import SimulatedPeriod

SWARM = SwarmParams(n_robots=3)
TUBE = VirtualTube(ArcPath((ArcPiece(30.0),)), WidthProfile(5.0, (WidthPart('constant', 30.0),)))
POINTS = np.array([[2.0, 5.0, 8.0], [0.0, 1.0, -1.0]])


def period(*, baseline=None, failure=None, latency: int = 0, limits: bool = False) -> SimulatedPeriod:
    stepper = SwarmStep(TUBE, ControlParams().step_params(SWARM), 3, constant_speed_mps=3.0)
    faults = Faults(
        0, pose_noise_m=0.0, dropout=0.0, latency_steps=latency, lag_s=0.0, dt_s=0.1, failure=failure,
        positions=POINTS,
        velocity=np.zeros((2, 3)),
    )  # fmt: skip
    return SimulatedPeriod(TUBE, SWARM, 0.1, limits, stepper, baseline, None, faults)


def test_the_controller_commands_what_the_swarm_step_does() -> None:
    p = period()
    velocity, density, r_a = p.command(0, POINTS, TUBE.project(POINTS), np.zeros((2, 3)))
    reference = SwarmStep(TUBE, ControlParams().step_params(SWARM), 3, constant_speed_mps=3.0)(POINTS, 0.1)
    np.testing.assert_array_equal(velocity, reference.velocity)
    assert density == reference.density_per_m2
    np.testing.assert_array_equal(r_a, reference.r_a_m)


def test_a_baseline_replaces_the_controller_and_the_density_is_still_measured() -> None:
    calls = []

    def baseline(positions, velocity, projection):
        calls.append(positions)
        return np.ones_like(positions)

    p = period(baseline=baseline)
    velocity, density, r_a = p.command(0, POINTS, TUBE.project(POINTS), np.zeros((2, 3)))
    np.testing.assert_array_equal(velocity, 1.0)
    assert density == pytest.approx(swarm_density(TUBE, POINTS[0], SWARM.r_a_m))
    assert density == pytest.approx(3 / (10.0 * (6.0 + 2 * SWARM.r_a_m)))
    np.testing.assert_array_equal(r_a, SWARM.r_a_m)
    assert len(calls) == 1


def test_the_next_velocity_is_the_command_or_held_to_the_limits() -> None:
    commanded = np.array([[3.0, 3.0, 3.0], [0.0, 0.0, 0.0]])
    np.testing.assert_array_equal(period().next_velocity(np.zeros((2, 3)), commanded, POINTS[0]), commanded)
    limited = period(limits=True).next_velocity(np.full((2, 3), [[1.0], [0.0]]), commanded, POINTS[0])
    np.testing.assert_allclose(limited[0], 1.0 + SWARM.a_v_mps2 * 0.1)


def test_latency_and_a_failed_robot_act_on_the_next_velocity() -> None:
    p = period(latency=1, failure=RobotFailure(robot=1, at_m=4.0))
    first = p.next_velocity(np.zeros((2, 3)), np.ones((2, 3)), POINTS[0])  # robot 1 at l = 5: failed, stops
    np.testing.assert_array_equal(first, np.zeros((2, 3)))  # the initial velocity, still in the pipe
    second = p.next_velocity(np.zeros((2, 3)), np.full((2, 3), 2.0), POINTS[0])
    np.testing.assert_array_equal(second, [[1.0, 0.0, 1.0], [1.0, 0.0, 1.0]])
    assert p.faults.working.tolist() == [True, False, True]
