"""Wheel speeds, curvature-keeping scaling and the always-realisable speed, on the GTernal's numbers."""

from __future__ import annotations

L_AXLE, R_WHEEL, PHI_MAX = 0.11, 0.016, 12.5  # GTernal / V2 simulator


import numpy as np
import pytest

from unicycle_mapping.mapping import si_to_uni
from unicycle_mapping.wheels import WHEEL_LIMIT_SHARE, max_realisable_si_speed, scale_to_wheel_limits, wheel_speeds


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


def test_no_scaled_wheel_rounds_over_the_limit_in_the_testbeds_own_formula() -> None:
    """The verifier recomputes wheel speeds as 1 / (2 r) (2 v -/+ L omega) and counts any over the limit: scaled to
    the limit itself, one command in a few thousand came out 1e-15 rad/s over it (a twenty-robot run counted one
    step); scaled to WHEEL_LIMIT_SHARE of it, none does, and the scaled wheel sits that close to the limit."""
    radius, length, limit = 0.016, 0.11, 12.5
    rng = np.random.default_rng(3)
    dxu = rng.uniform(-1.0, 1.0, (2, 200_000)) * np.array([[0.4], [8.0]])

    def testbed_wheels(commands: np.ndarray) -> np.ndarray:
        return (
            1
            / (2 * radius)
            * np.vstack([2 * commands[0] - length * commands[1], 2 * commands[0] + length * commands[1]])
        )

    scaled, scale = scale_to_wheel_limits(dxu, length, radius, limit)
    fastest = np.abs(testbed_wheels(scaled)).max(axis=0)
    assert not np.any(fastest > limit)
    np.testing.assert_allclose(fastest[scale < 1.0], limit * WHEEL_LIMIT_SHARE, rtol=1e-14)
    at_limit = dxu * np.where(scale < 1.0, limit / np.abs(wheel_speeds(dxu, length, radius)).max(axis=0), 1.0)
    assert np.any(np.abs(testbed_wheels(at_limit)).max(axis=0) > limit)  # the rounding this guards against
