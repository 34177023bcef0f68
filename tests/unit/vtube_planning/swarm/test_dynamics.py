"""The robot model (1)-(4): the response to a command in closed form, and the count of commands outside the
model, checked against an independent loop over the logged velocities."""

from __future__ import annotations

import math

import numpy as np

from vtube_planning.params import SwarmParams
from vtube_planning.swarm.dynamics import dynamics_violations, limit_acceleration, respond


def test_speed_changes_by_at_most_a_v_dt() -> None:
    v = limit_acceleration(np.array([[1.0], [0.0]]), np.array([[3.0], [0.0]]), 1.0, 1.0, 0.5)
    np.testing.assert_allclose(v, [[1.5], [0.0]])
    v = limit_acceleration(np.array([[2.0], [0.0]]), np.array([[1.8], [0.0]]), 1.0, 1.0, 0.5)
    np.testing.assert_allclose(v, [[1.8], [0.0]])  # within the limit: the command itself


def test_the_heading_turns_by_at_most_a_n_dt_over_the_new_speed() -> None:
    v = limit_acceleration(np.array([[1.0], [0.0]]), np.array([[0.0], [1.0]]), 1.0, 0.5, 0.2)
    np.testing.assert_allclose(v, [[math.cos(0.1)], [math.sin(0.1)]])
    v = limit_acceleration(np.array([[0.0], [-1.0]]), np.array([[-1.0], [0.0]]), 1.0, 0.5, 0.2)  # turns right
    np.testing.assert_allclose(v, [[-math.sin(0.1)], [-math.cos(0.1)]], atol=1e-15)


def test_random_commands_respect_both_limits() -> None:
    rng = np.random.default_rng(4)
    velocity, command = rng.normal(0, 2, (2, 500)), rng.normal(0, 2, (2, 500))
    after = limit_acceleration(velocity, command, 0.8, 1.2, 0.05)
    speed, new = np.hypot(*velocity), np.hypot(*after)
    assert np.all(np.abs(new - speed) <= 0.8 * 0.05 + 1e-12)
    turn = np.abs(np.angle(np.exp(1j * (np.arctan2(after[1], after[0]) - np.arctan2(velocity[1], velocity[0])))))
    assert np.all(new * turn <= 1.2 * 0.05 + 1e-12)


def test_a_held_target_is_reached_in_the_time_the_limits_give() -> None:
    # from 2 m/s heading east to 4 m/s heading north at a_v = 1, a_n = 2: the speed arrives after 2 s, while the
    # heading turns at a_n / v(t) = 2 / (2 + t), by 2 ln 2 in those 2 s; the rest, pi/2 - 2 ln 2, at 2 / 4 rad/s:
    # t = 2 + pi - 4 ln 2 = 2.369 s
    speed, heading, dt = np.array([2.0]), np.array([0.0]), 1e-4
    t = 0.0
    while abs(heading[0] - math.pi / 2) > 1e-12:
        speed, heading = respond(speed, heading, np.array([4.0]), np.array([math.pi / 2]), 1.0, 2.0, dt)
        t += dt
    assert abs(t - (2.0 + math.pi - 4.0 * math.log(2.0))) < 1e-3
    assert speed[0] == 4.0


def _violations_by_loop(velocities, commands, band, a_v, a_n, dt) -> int:
    """The count, one robot-period at a time in plain Python: the independent check."""
    count = 0
    for k in range(velocities.shape[0]):
        for i in range(velocities.shape[2]):
            vx, vy = velocities[k, :, i]
            cx, cy = commands[k, :, i]
            if any(math.isnan(x) for x in (vx, vy, cx, cy)):
                continue
            speed, target = math.hypot(vx, vy), math.hypot(cx, cy)
            turn = abs(math.remainder(math.atan2(cy, cx) - math.atan2(vy, vx), 2 * math.pi))
            broken = not band[0] - 1e-9 <= target <= band[1] + 1e-9
            broken = broken or abs(target - speed) > a_v * dt + 1e-9 or target * turn > a_n * dt * (1 + 1e-9) + 1e-9
            count += broken
    return count


def test_violations_match_an_independent_count_on_random_logs() -> None:
    rng = np.random.default_rng(7)
    for _ in range(5):
        velocities = rng.uniform(-4, 4, (30, 2, 6))
        # half the commands are reachable (the model's own response), half arbitrary
        commands = limit_acceleration(
            velocities.transpose(1, 0, 2).reshape(2, -1), rng.uniform(-5, 5, (2, 180)), 1.0, 1.0, 0.1
        )
        commands = commands.reshape(2, 30, 6).transpose(1, 0, 2)
        commands[::2] = rng.uniform(-5, 5, commands[::2].shape)
        commands[3, :, 2] = np.nan  # a robot without a record
        got = dynamics_violations(velocities, commands, SwarmParams(v_min_mps=1.0, v_max_mps=5.0), 0.1)
        assert got == _violations_by_loop(velocities, commands, (1.0, 5.0), 1.0, 1.0, 0.1)
        assert 0 < got < 180


def test_the_model_s_own_responses_are_never_violations() -> None:
    rng = np.random.default_rng(8)
    speed = rng.uniform(2, 5, (40, 8))
    heading = rng.uniform(-math.pi, math.pi, (40, 8))
    velocities = np.stack([speed * np.cos(heading), speed * np.sin(heading)], axis=1)
    targets = np.stack([rng.uniform(2, 5, (40, 8)), rng.uniform(-math.pi, math.pi, (40, 8))])
    new_speed, new_heading = respond(speed, heading, targets[0], targets[1], 1.0, 1.0, 0.02)
    commands = np.stack([new_speed * np.cos(new_heading), new_speed * np.sin(new_heading)], axis=1)
    assert dynamics_violations(velocities, commands, SwarmParams(), 0.02) == 0
    assert dynamics_violations(velocities, commands, SwarmParams(a_v_mps2=0.5), 0.02) > 0  # tighter limits: caught
