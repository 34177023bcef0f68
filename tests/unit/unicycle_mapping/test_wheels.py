"""Wheel speeds, curvature-keeping scaling and the always-realisable speed, on the GTernal's numbers."""

from __future__ import annotations

L_AXLE, R_WHEEL, PHI_MAX = 0.11, 0.016, 12.5  # GTernal / V2 simulator


import numpy as np
import pytest

from unicycle_mapping.mapping import si_to_uni
from unicycle_mapping.wheels import max_realisable_si_speed, scale_to_wheel_limits, wheel_speeds


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
