"""The near-identity map, its speed-constrained variant, wheel limits and the exact unicycle step."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from unicycle_mapping.errors import MappingError
from unicycle_mapping.mapping import si_to_uni, si_to_uni_constrained, si_to_uni_states, uni_to_si, uni_to_si_states
from unicycle_mapping.unicycle import unicycle_step
from unicycle_mapping.wheels import scale_to_wheel_limits


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


def test_with_finite_false_nan_and_inf_propagate_column_by_column_instead_of_being_refused() -> None:
    """The Robotarium's own maps (V2's ``rps.utilities.transformations``) let them through: the other robots'
    answers are the finite ones, the robot with NaN or inf gets IEEE's answer (inf * 0 is NaN)."""
    rng = np.random.default_rng(4)
    poses, u, d = random_poses(rng, 4), rng.normal(0, 0.2, (2, 4)), 0.05
    poses[2, 0], u[0, 1], u[1, 2] = np.nan, np.inf, np.nan
    poses[2, 1] = 0.0  # heading along x: v = inf, omega = (-0 * inf + u_y) / d = NaN
    for call, args in ((si_to_uni, (u, poses)), (uni_to_si, (u, poses)), (uni_to_si_states, (poses,))):
        with pytest.raises(MappingError, match='must be finite'):
            call(*args, d)
        with np.errstate(invalid='ignore'):  # numpy warns of inf * 0, as on the Robotarium's maps
            answer = call(*args, d, finite=False)
        finite_columns = [3] if call is not uni_to_si_states else [1, 2, 3]
        np.testing.assert_array_equal(answer[:, finite_columns], call(*(a[:, finite_columns] for a in args), d))
        assert np.isnan(answer[:, 0]).all()
    with np.errstate(invalid='ignore'):
        mapped = si_to_uni(u, poses, d, finite=False)
    assert mapped[0, 1] == np.inf and np.isnan(mapped[1, 1]) and np.isnan(mapped[:, 2]).all()
