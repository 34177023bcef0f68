"""The foresight: the law's command let through where it is safe, replaced by a command inside (2)-(4) where it is
not; the closest approach between predicted points; the announced backup kept (the short flights that collide without it and not with it:
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
from vtube_planning.swarm import foresight as foresight_module
from vtube_planning.swarm.dynamics import dynamics_violations, limit_acceleration, respond
from vtube_planning.swarm.foresight import Foresight, _Backups, _free, _Robots
from vtube_planning.swarm.foresight_kernel import changing, closest_squared

_closest_squared = np.vectorize(closest_squared)

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
    behind, ahead = commanded[:, 0], commanded[:, 1]
    closing = np.hypot(*behind) - np.hypot(*ahead)
    assert closing < 2.0 or abs(behind[1]) > 0.0  # the gap closes slower (one slows, or the other speeds up) or
    # the one behind steers out of line


def test_the_closest_approach_over_a_step_is_the_densely_sampled_one() -> None:
    rng = np.random.default_rng(8)
    start, end = rng.normal(0.0, 2.0, (2, 2, 300))
    closest = np.sqrt(_closest_squared(start[0], start[1], end[0], end[1]))
    t = np.linspace(0.0, 1.0, 4001)[:, None]
    sampled = np.hypot(start[0] + t * (end[0] - start[0]), start[1] + t * (end[1] - start[1])).min(axis=0)
    np.testing.assert_allclose(closest, sampled, atol=3e-3)
    assert (closest <= np.minimum(np.hypot(*start), np.hypot(*end)) + 1e-15).all()
    # two robots crossing between the two predicted points: 2 m apart at both, 0 between
    assert _closest_squared(np.array([-1.0]), np.array([0.0]), np.array([1.0]), np.array([0.0]))[0] == 0.0


@pytest.mark.parametrize(('start', 'target'), [(5.0, 2.0), (2.0, 5.0), (3.0, 3.6)])
def test_a_predicted_flight_is_where_the_simulator_takes_the_robot(start: float, target: float) -> None:
    # oracle: the simulator's own rule (`respond`, then a period at the new velocity) in 0.02 s periods, on the
    # centre lane of a straight tube: the prediction's long steps land where the periods do (moving at the end
    # velocity of each long step instead would leave a braking robot 0.6 m short after 3 s)
    foresight = Foresight(STRAIGHT, SwarmParams(n_robots=1), horizon_s=0.02 + 7 * 0.42, acceleration_limits=True)
    robots = _Robots(np.array([[5.0], [0.0]]), np.array([start]), np.zeros(1), np.array([5.0]), np.zeros(1))
    speed = np.array([[target]])
    flights = foresight._flights(robots, _Backups(np.arange(1), np.zeros((1, 1)), speed, *_free(speed)), 0.02)
    x, v, elapsed = 5.0, start, 0.0
    for step, px, py in zip(foresight._times(0.02), flights[0], flights[1], strict=True):
        for _ in range(round(step / 0.02)):
            v = float(respond(np.array(v), np.array(0.0), np.array(target), np.array(0.0), 1.0, 1.0, 0.02)[0])
            x += 0.02 * v
        elapsed += step
        assert abs(px[0, 0] - x) < 0.5 * 0.02 * elapsed + 1e-9  # periods: a_v dt / 2 m short per second
        assert abs(py[0, 0]) < 1e-12


def test_a_velocity_changes_for_as_long_as_the_limits_make_it_take() -> None:
    # analytic: a speed change takes |dv| / a_v, a turn |dtheta| v / a_n (v the new speed), the longer of the two,
    # at most the step; in the paper's model (no a_v, a_n) a velocity changes at once
    during = np.vectorize(changing)
    speed, heading = np.array([3.0, 3.0, 3.0, 3.0]), np.array([0.0, 0.0, 0.5, 0.0])
    new_speed, new_heading = np.array([3.3, 3.2, 3.0, 3.6]), np.array([0.0, 0.1, 0.4, 0.2])
    limited = during(speed, heading, new_speed, new_heading, 0.43, 1.0, 1.0)
    np.testing.assert_allclose(limited, [0.3, max(0.2, 0.1 * 3.2), 0.1 * 3.0, 0.43], rtol=1e-12)  # 0.43: capped
    assert (during(speed, heading, new_speed, new_heading, 0.43, math.inf, math.inf) == 0.0).all()


def test_a_robot_whose_backups_all_fall_short_keeps_the_one_it_announced() -> None:
    foresight = _foresight(STRAIGHT, 2)
    positions = np.array([[5.0, 5.0], [-0.3, 0.3]])  # 0.6 m apart, side by side: every backup is short
    velocity = np.array([[3.0, 3.0], [0.0, 0.0]])
    chosen = []
    for _ in range(10):
        commanded = foresight(positions, velocity, velocity.copy(), 0.02)
        chosen.append((foresight.announced[0].copy(), foresight.announced[1].copy()))
        positions = positions + 0.02 * commanded
        velocity = commanded
    lanes = np.array([c[0] for c in chosen[1:]])
    speeds = np.array([c[1] for c in chosen[1:]])
    assert (np.abs(np.diff(speeds, axis=0)) < 1e-12).all()  # no turns taken between slow and fast backups
    assert (np.abs(np.diff(lanes, axis=0)) < 0.05).all()
    assert lanes[-1, 0] < 0.0 < lanes[-1, 1]  # and the ones kept part them


def test_in_order_the_robot_behind_chooses_against_what_the_robot_ahead_just_chose(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    def decided(
        passes: int, told: tuple[np.ndarray, np.ndarray], positions: np.ndarray, velocity: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        monkeypatch.setattr(foresight_module, 'PASSES', passes)
        foresight = _foresight(STRAIGHT, 2)
        foresight.announced = (told[0].copy(), told[1].copy())
        foresight._held = np.full(2, foresight_module.HOLD_S)  # both fly backups: both choose
        foresight(positions, velocity, velocity.copy(), 0.02)
        assert foresight.announced is not None
        return foresight.announced

    changed = 0
    for seed in range(12):
        rng = np.random.default_rng(seed)  # two robots 0.8 m apart across, robot 0 up to 1.5 m ahead
        positions = np.array([[5.0 + rng.uniform(0.0, 1.5), 5.0], rng.uniform(-1.5, 1.5) + np.array([-0.4, 0.4])])
        velocity = np.vstack([rng.uniform(2.0, 5.0, 2), np.zeros(2)])
        announced = (rng.uniform(-1.0, 1.0, 2), rng.uniform(2.0, 5.0, 2))
        in_order = decided(2, announced, positions, velocity)
        first = decided(1, announced, positions, velocity)
        # robot 1 chooses again, seeing robot 0's fresh choice as if robot 0 had announced it
        fresh = (np.array([first[0][0], announced[0][1]]), np.array([first[1][0], announced[1][1]]))
        again = decided(1, fresh, positions, velocity)
        assert (in_order[0][0], in_order[1][0]) == (first[0][0], first[1][0])  # the one ahead: as it first chose
        assert (in_order[0][1], in_order[1][1]) == (again[0][1], again[1][1])
        changed += (in_order[0][1], in_order[1][1]) != (first[0][1], first[1][1])
    assert changed >= 2  # robots behind that chose otherwise in order: the cases test something
