"""The foresight: the tube's tables against the exact projection, the law's command let through where it is safe,
replaced by a command inside (2)-(4) where it is not (the short flights that collide without it and not with it:
``tests/integration/test_foresight_flights.py``)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.params import SwarmParams
from vtube_planning.swarm.dynamics import dynamics_violations, limit_acceleration
from vtube_planning.swarm.foresight import Foresight, TubeTables

SWARM = SwarmParams(n_robots=2)
STRAIGHT = VirtualTube(ArcPath((ArcPiece(40.0),)), WidthProfile(3.0, (WidthPart('constant', 40.0),)))
BENT = VirtualTube(
    ArcPath(
        (
            ArcPiece(5.0),
            ArcPiece(12.0, radius_m=10.0),
            ArcPiece(5.0),
            ArcPiece(10.0, radius_m=8.0, left=False),
            ArcPiece(8.0),
        )
    ),
    WidthProfile(2.0, (WidthPart('constant', 40.0),)),
)


@pytest.mark.parametrize('tube', [STRAIGHT, BENT], ids=['straight', 'bent'])
def test_the_tables_locate_points_as_the_projection_does(tube: VirtualTube) -> None:
    tables = TubeTables.of(tube, 5.0)
    rng = np.random.default_rng(3)
    l_true = rng.uniform(0.0, tube.length_m, 500)
    y_true = rng.uniform(-0.95, 0.95, 500) * np.asarray(tube.half_width(l_true))
    points = tube.center_at(l_true).T + y_true * tube.normal(l_true).T
    l_m, offset = tables.locate(points[0], points[1], l_true + rng.uniform(-1.0, 1.0, 500))  # a guess 1 m off
    exact = tube.project(points)
    np.testing.assert_allclose(l_m, exact.l_m, atol=2e-3)
    np.testing.assert_allclose(offset, exact.y_m, atol=2e-3)
    clearance = tables.clearance(l_m, offset)
    np.testing.assert_allclose(clearance, exact.clearance_m, atol=3e-3)
    assert np.isinf(tables.clearance(np.array([-1.0, tube.length_m + 1.0]), np.zeros(2))).all()


def _foresight(tube: VirtualTube, n: int) -> Foresight:
    return Foresight(tube, replace(SWARM, n_robots=n), horizon_s=3.0, acceleration_limits=True)


def test_a_safe_command_is_followed_as_the_robot_can() -> None:
    foresight = _foresight(STRAIGHT, 2)
    positions = np.array([[5.0, 5.0], [-1.0, 1.0]])  # side by side, 2 m apart, flying along the tube
    velocity = np.array([[3.0, 3.0], [0.0, 0.0]])
    command = np.array([[4.0, 2.5], [0.0, 0.0]])  # one speeds up, one slows: both stay apart and inside
    commanded = foresight(positions, velocity, command, 0.02)
    np.testing.assert_allclose(commanded, limit_acceleration(velocity, command, 1.0, 1.0, 0.02), atol=1e-12)
    assert foresight.overridden == 0


def test_a_command_into_the_wall_is_replaced_by_one_inside_the_model() -> None:
    foresight = _foresight(STRAIGHT, 1)
    positions = np.array([[5.0], [2.2]])  # 0.8 m from the wall
    velocity = np.array([[4.0 * math.cos(0.5)], [4.0 * math.sin(0.5)]])  # heading for it at 4 m/s (radius 16 m)
    command = velocity.copy()  # the law says: keep going
    commanded = foresight(positions, velocity, command, 0.02)
    assert foresight.overridden == 1
    heading = math.atan2(commanded[1, 0], commanded[0, 0])
    assert heading < 0.5  # turns away from the wall
    assert dynamics_violations(velocity[None], commanded[None], SwarmParams(), 0.02) == 0


def test_a_robot_about_to_hit_the_one_ahead_gives_way() -> None:
    foresight = _foresight(STRAIGHT, 2)
    positions = np.array([[5.0, 7.0], [0.0, 0.0]])  # 2 m behind, 2 m/s faster
    velocity = np.array([[4.0, 2.0], [0.0, 0.0]])
    commanded = foresight(positions, velocity, velocity.copy(), 0.02)
    assert foresight.overridden >= 1
    behind = commanded[:, 0]
    assert np.hypot(*behind) < 4.0 or abs(behind[1]) > 0.0  # slows down or steers out of line
