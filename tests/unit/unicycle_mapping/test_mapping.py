"""The near-identity map, its speed-constrained variant, wheel limits and the exact unicycle step."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from unicycle_mapping import (
    MappingError,
    max_realisable_si_speed,
    scale_to_wheel_limits,
    si_to_uni,
    si_to_uni_constrained,
    si_to_uni_states,
    uni_to_si,
    uni_to_si_states,
    unicycle_step,
    wheel_speeds,
)

L_AXLE, R_WHEEL, PHI_MAX = 0.11, 0.016, 12.5  # GTernal / V2 simulator


def random_poses(rng: np.random.Generator, n: int) -> np.ndarray:
    return np.vstack([rng.uniform(-1.5, 1.5, n), rng.uniform(-1, 1, n), rng.uniform(-np.pi, np.pi, n)])


@pytest.mark.parametrize('seed', range(5))
def test_round_trip_is_the_identity(seed: int) -> None:
    rng = np.random.default_rng(seed)
    poses, u = random_poses(rng, 50), rng.normal(0, 0.2, (2, 50))
    d = rng.uniform(0.01, 0.2)
    np.testing.assert_allclose(uni_to_si(si_to_uni(u, poses, d), poses, d), u, atol=1e-12)
    dxu = rng.normal(0, 0.5, (2, 50))
    np.testing.assert_allclose(si_to_uni(uni_to_si(dxu, poses, d), poses, d), dxu, atol=1e-12)
    points = uni_to_si_states(poses, d)
    np.testing.assert_allclose(si_to_uni_states(points, poses[2], d), poses, atol=1e-12)
    np.testing.assert_allclose(np.hypot(*(points - poses[:2])), d, atol=1e-15)


def test_control_point_velocity_matches_the_command_by_finite_differences() -> None:
    rng = np.random.default_rng(7)
    poses, u, d, h = random_poses(rng, 40), rng.normal(0, 0.3, (2, 40)), 0.05, 1e-6
    dxu = si_to_uni(u, poses, d)
    ahead = uni_to_si_states(unicycle_step(poses, dxu, h), d)
    behind = uni_to_si_states(unicycle_step(poses, dxu, -h), d)
    np.testing.assert_allclose((ahead - behind) / (2 * h), u, atol=1e-8)


def test_epsilon_tracking_of_a_moving_reference() -> None:
    d, gain = 0.05, 2.0

    def reference(t: float) -> tuple[np.ndarray, np.ndarray]:
        r = np.array([0.8 * math.cos(0.5 * t), 0.5 * math.sin(t)])
        return r, np.array([-0.4 * math.sin(0.5 * t), 0.5 * math.cos(t)])

    r0, _ = reference(0.0)
    pose0 = si_to_uni_states(r0[:, None], np.array([0.3]), d)[:, 0]  # control point on the reference

    def closed_loop(t: float, pose: np.ndarray) -> np.ndarray:
        r, r_dot = reference(t)
        p = uni_to_si_states(pose[:, None], d)[:, 0]
        v, omega = si_to_uni((r_dot + gain * (r - p))[:, None], pose[:, None], d)[:, 0]
        return np.array([v * math.cos(pose[2]), v * math.sin(pose[2]), omega])

    t = np.linspace(0.0, 20.0, 401)
    sol = solve_ivp(closed_loop, (0.0, 20.0), pose0, t_eval=t, rtol=1e-11, atol=1e-12, method='DOP853')
    refs = np.array([reference(s)[0] for s in t]).T
    error = np.hypot(*(uni_to_si_states(sol.y, d) - refs))
    assert error.max() < 1e-6
    assert np.all(np.hypot(*(sol.y[:2] - refs)) <= d + 1e-6)


@pytest.mark.parametrize('seed', range(5))
def test_uniform_wheel_scaling_respects_the_limit_and_the_curvature(seed: int) -> None:
    rng = np.random.default_rng(seed)
    dxu = np.vstack([rng.uniform(-0.5, 0.5, 200), rng.uniform(-8, 8, 200)])
    scaled, scale = scale_to_wheel_limits(dxu, L_AXLE, R_WHEEL, PHI_MAX)
    assert np.abs(wheel_speeds(scaled, L_AXLE, R_WHEEL)).max() <= PHI_MAX * (1 + 1e-12)
    moving = np.abs(dxu[0]) > 1e-3
    np.testing.assert_allclose(scaled[1, moving] / scaled[0, moving], dxu[1, moving] / dxu[0, moving], rtol=1e-12)
    feasible = np.abs(wheel_speeds(dxu, L_AXLE, R_WHEEL)).max(axis=0) <= PHI_MAX
    np.testing.assert_array_equal(scaled[:, feasible], dxu[:, feasible])  # untouched when already feasible
    assert np.all((scale > 0) & (scale <= 1))


def test_wheel_speeds_by_hand_and_the_testbed_limit() -> None:
    # v = 0.1 m/s, omega = 1 rad/s: (0.2 -/+ 0.11) / 0.032
    np.testing.assert_allclose(wheel_speeds(np.array([[0.1], [1.0]]), L_AXLE, R_WHEEL)[:, 0], [2.8125, 9.6875])
    # the feasible set |v| + (L/2)|omega| <= r phi_max = 0.2 m/s: on its edge a wheel is exactly at the limit
    edge = np.array([[0.2 - 0.055 * 2.0], [2.0]])
    assert np.abs(wheel_speeds(edge, L_AXLE, R_WHEEL)).max() == pytest.approx(PHI_MAX)


@pytest.mark.parametrize(
    ('d', 'length', 'expected'), [(0.05, 0.11, 0.134), (0.03, 0.11, 0.096), (0.05, 0.105, 0.138), (0.03, 0.105, 0.099)]
)
def test_realisable_speed_matches_the_robotarium_table_and_is_tight(d: float, length: float, expected: float) -> None:
    bound = max_realisable_si_speed(d, length, R_WHEEL, PHI_MAX)
    assert bound == pytest.approx(expected, abs=1e-3)  # the table prints three digits (0.1345 as 0.134)
    alpha = np.linspace(-np.pi, np.pi, 3601)
    for speed, ok in ((bound, True), (1.01 * bound, False)):
        u = speed * np.vstack([np.cos(alpha), np.sin(alpha)])
        worst = np.abs(wheel_speeds(si_to_uni(u, np.zeros((3, alpha.size)), d), length, R_WHEEL)).max()
        assert bool(worst <= PHI_MAX * (1 + 1e-9)) == ok


def test_speed_constrained_map_clips_and_loiters() -> None:
    d, v_min, v_max, a_n = 0.05, 0.04, 0.12, 0.02
    poses = np.zeros((3, 4))  # all heading along +x
    u = np.array([[0.08, 0.30, 0.01, -0.10], [0.0001, 0.0, 0.0, 0.0]])
    dxu, exact = si_to_uni_constrained(u, poses, d, v_min=v_min, v_max=v_max, a_n=a_n)
    np.testing.assert_allclose(dxu[0], [0.08, v_max, v_min, v_min])
    np.testing.assert_allclose(dxu[1, :3], [0.0001 / d, 0.0, 0.0])
    assert dxu[1, 3] == pytest.approx(a_n / v_min)  # straight back: turn left at the largest rate, never reverse
    np.testing.assert_array_equal(exact, [True, False, False, False])
    rng = np.random.default_rng(3)
    poses, u = random_poses(rng, 300), rng.normal(0, 0.2, (2, 300))
    dxu, exact = si_to_uni_constrained(u, poses, d, v_min=v_min, v_max=v_max, a_n=a_n)
    assert np.all((dxu[0] >= v_min) & (dxu[0] <= v_max))
    assert np.all(np.abs(dxu[1]) <= a_n / dxu[0] * (1 + 1e-12))
    np.testing.assert_allclose(uni_to_si(dxu[:, exact], poses[:, exact], d), u[:, exact], atol=1e-12)


def test_unicycle_step_is_exact_for_constant_commands() -> None:
    pose = np.array([[0.0], [0.0], [0.0]])
    # a quarter circle of radius 0.5 at v = 0.1, omega = 0.2 takes pi / 0.4 s
    end = unicycle_step(pose, np.array([[0.1], [0.2]]), math.pi / 0.4)
    np.testing.assert_allclose(end[:, 0], [0.5, 0.5, math.pi / 2], atol=1e-15)
    straight = unicycle_step(np.array([[1.0], [2.0], [math.pi / 4]]), np.array([[0.2], [0.0]]), 2.0)
    np.testing.assert_allclose(straight[:, 0], [1.0 + 0.4 / math.sqrt(2), 2.0 + 0.4 / math.sqrt(2), math.pi / 4])
    many = pose
    for _ in range(1000):  # composition: 1000 small exact steps equal one large one
        many = unicycle_step(many, np.array([[0.1], [0.2]]), math.pi / 400)
    np.testing.assert_allclose(many[:, 0], end[:, 0], atol=1e-12)


@pytest.mark.parametrize(
    ('call', 'match'),
    [
        (lambda: si_to_uni(np.zeros((2, 3)), np.zeros((2, 3)), 0.05), r'poses must have shape \(3, N\).*got \(2, 3\)'),
        (lambda: si_to_uni(np.zeros((2, 4)), np.zeros((3, 3)), 0.05), r'dxi must have shape \(2, 3\).*got \(2, 4\)'),
        (
            lambda: si_to_uni(np.zeros((2, 3)), np.zeros((3, 3)), 0.0),
            'projection distance d must be a finite number > 0',
        ),
        (lambda: uni_to_si(np.array([[0.1], [np.nan]]), np.zeros((3, 1)), 0.05), r'columns \[0\] of shape \(2, 1\)'),
        (lambda: unicycle_step(np.zeros((3, 2)), np.zeros((2,)), 0.03), r'got \(2,\)'),
        (lambda: unicycle_step(np.zeros((3, 2)), np.zeros((2, 2)), float('inf')), 'dt_s must be a finite number'),
        (lambda: scale_to_wheel_limits(np.zeros((2, 1)), 0.11, -1.0, 12.5), 'wheel_radius_m must be'),
        (
            lambda: si_to_uni_constrained(np.zeros((2, 1)), np.zeros((3, 1)), 0.05, v_min=0.2, v_max=0.1, a_n=1.0),
            r'v_min \(0.2\) exceeds v_max \(0.1\)',
        ),
    ],
)
def test_bad_input_raises_value_error_with_the_shape(call, match: str) -> None:
    with pytest.raises(MappingError, match=match):
        call()
    assert issubclass(MappingError, ValueError)
