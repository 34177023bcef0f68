"""The avoidance radius law (a3): only expands, capped, floored by the feed-forward."""

from __future__ import annotations

import numpy as np

from vtube_planning.onboard.radius import avoidance_radius_rate, feedforward_radius, next_radius
from vtube_planning.params import ControlParams, SwarmParams

SWARM = SwarmParams()  # r_s = 0.4, r_a = 0.8, v in [2, 5]


def test_avoidance_radius_law_only_expands() -> None:
    params = ControlParams(k_ra_m3ps=4.0).step_params(SWARM)
    rate = avoidance_radius_rate(0.3, np.array([0.2, 0.3, 0.5]), params)
    np.testing.assert_allclose(rate, [0.4, 0.0, 0.0])
    np.testing.assert_allclose(feedforward_radius(np.array([0.25]), params), [2.0 - 0.4])  # 1/sqrt(rho) - r_s


def test_avoidance_radius_update_caps_and_feeds_forward() -> None:
    r_a = np.array([0.8, 1.0, 2.3])
    plain = ControlParams(k_ra_m3ps=4.0, r_a_max_m=2.4).step_params(SWARM)
    # rate 4 (0.3 - rho*): 0.4, 0.0, 0.4 m/s over 0.5 s; the third robot stops at the cap
    np.testing.assert_allclose(next_radius(r_a, 0.3, np.array([0.2, 0.5, 0.2]), plain, 0.5), [1.0, 1.0, 2.4])
    fed = ControlParams(k_ra_m3ps=4.0, r_a_max_m=2.4, feedforward=True).step_params(SWARM)
    # rho* = 0.25 -> 1/sqrt(rho*) - r_s = 1.6 m floors the first two; rho* = 0.01 -> 9.6 m, capped at 2.4
    np.testing.assert_allclose(next_radius(r_a, 0.3, np.array([0.25, 0.25, 0.01]), fed, 0.5), [1.6, 1.6, 2.4])
