"""Density tracking along the tube (`vtube_planning.onboard.stretch`)."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.onboard.stretch import stretched_speed

BAND = (0.04, 0.12)


def test_a_denser_swarm_lengthens_and_a_sparser_one_closes_up() -> None:
    """Three robots at l = 0, 1, 2 (centre 1, half length 1), v* = 0.08: 20 % too dense with g = 0.1 spreads the
    speeds by 0.02 either way, the front faster; 50 % too sparse with g = 0.06 by 0.03 the other way."""
    forward = np.full(3, 0.08)
    l_m = np.array([0.0, 1.0, 2.0])
    np.testing.assert_allclose(stretched_speed(forward, l_m, l_m, 1.2, 1.0, 0.1, BAND), [0.06, 0.08, 0.10])
    np.testing.assert_allclose(stretched_speed(forward, l_m, l_m, 0.5, 1.0, 0.06, BAND), [0.11, 0.08, 0.05])


def test_the_error_and_the_place_are_clipped_and_the_speeds_kept_in_the_band() -> None:
    """Five times the plan counts as 100 % too dense; a robot outside the swarm's span (a parked one) counts as its
    end; the speeds stay within [v_min, v_max]."""
    forward = np.full(4, 0.08)
    swarm = np.array([0.0, 1.0, 2.0])
    l_m = np.array([0.0, 1.0, 2.0, 7.0])
    out = stretched_speed(forward, l_m, swarm, 5.0, 1.0, 0.03, BAND)
    np.testing.assert_allclose(out, [0.05, 0.08, 0.11, 0.11])
    wide = stretched_speed(forward, l_m, swarm, 5.0, 1.0, 1.0, BAND)
    np.testing.assert_allclose(wide, [0.04, 0.08, 0.12, 0.12])


@pytest.mark.parametrize('gain', [0.0, 0.2])
def test_nothing_stretches_without_a_gain_or_a_length(gain: float) -> None:
    """Gain 0 returns the plan's speeds untouched; so does a swarm whose robots share one arc length."""
    forward = np.array([0.05, 0.07, 0.09])
    spot = np.full(3, 4.0)
    assert stretched_speed(forward, spot, spot, 3.0, 1.0, gain, BAND) is forward
    if gain == 0.0:
        l_m = np.array([0.0, 1.0, 2.0])
        assert stretched_speed(forward, l_m, l_m, 3.0, 1.0, gain, BAND) is forward


def test_random_swarms_keep_their_mean_speed_where_nothing_clips() -> None:
    """Property: for a swarm placed symmetrically about its centre, within the band, the stretch moves speed from
    the rear to the front and keeps the mean; its sign follows the error's."""
    rng = np.random.default_rng(3)
    for _ in range(200):
        half = rng.uniform(0.1, 2.0, 4)
        l_m = np.sort(np.concatenate([5.0 - half, 5.0 + half]))
        forward = np.full(8, 0.08)
        rho, plan = rng.uniform(0.5, 1.5), 1.0
        out = stretched_speed(forward, l_m, l_m, rho, plan, 0.03, BAND)
        assert out.mean() == pytest.approx(0.08, abs=1e-12)
        assert np.sign(out[-1] - out[0]) == np.sign(rho - plan) or rho == plan
