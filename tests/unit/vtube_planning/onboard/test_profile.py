"""PlanProfile: slowness and density linear between grid points, the end values held outside."""

from __future__ import annotations

import numpy as np

from vtube_planning.onboard.profile import PlanProfile

PROFILE = PlanProfile(np.array([0.0, 2.0, 6.0]), np.array([0.5, 0.25, 0.2]), np.array([0.1, 0.3, 0.2]))


def test_speed_is_one_over_the_interpolated_slowness() -> None:
    # at l = 1: w = 0.375 -> v = 1/0.375; at l = 4: w = 0.225 (not the mean of the speeds 4 and 5)
    np.testing.assert_allclose(PROFILE.speed([0.0, 1.0, 2.0, 4.0, 6.0]), [2.0, 1 / 0.375, 4.0, 1 / 0.225, 5.0])


def test_density_is_linear_between_grid_points() -> None:
    np.testing.assert_allclose(PROFILE.density([0.0, 1.0, 2.0, 4.0, 6.0]), [0.1, 0.2, 0.3, 0.25, 0.2])


def test_end_values_hold_beyond_the_grid() -> None:
    np.testing.assert_allclose(PROFILE.speed([-5.0, 100.0]), [2.0, 5.0])
    np.testing.assert_allclose(PROFILE.density([-5.0, 100.0]), [0.1, 0.2])


def test_random_arc_lengths_match_an_independent_interpolation() -> None:
    rng = np.random.default_rng(1)
    l_m = rng.uniform(0.0, 6.0, 50)
    k = np.searchsorted(PROFILE.l_m, l_m, side='right') - 1
    k = np.minimum(k, 1)
    u = (l_m - PROFILE.l_m[k]) / (PROFILE.l_m[k + 1] - PROFILE.l_m[k])
    w = (1 - u) * PROFILE.slowness_spm[k] + u * PROFILE.slowness_spm[k + 1]
    np.testing.assert_allclose(PROFILE.speed(l_m), 1.0 / w, rtol=1e-12)
    assert PROFILE.speed(3.0).shape == ()
