"""Classic transformations: the si-to-uni dynamics and mappings."""

from __future__ import annotations

import numpy as np

import robotarium_exp.rps.utilities.transformations as v2_transformations
import robotarium_exp.rps_classic.utilities.transformations as classic_transformations


def test_si_to_uni_dynamics_gain_enters_the_turn_rate(states) -> None:
    x, goals = states
    dxi = goals[:2]
    dxu = classic_transformations.create_si_to_uni_dynamics(linear_velocity_gain=0.5, angular_velocity_limit=2.0)(
        dxi, x
    )
    along = np.cos(x[2]) * dxi[0] + np.sin(x[2]) * dxi[1]
    across = -np.sin(x[2]) * dxi[0] + np.cos(x[2]) * dxi[1]
    np.testing.assert_allclose(dxu, [0.5 * along, 2.0 * np.arctan2(across, 0.5 * along) / (np.pi / 2)], atol=1e-14)
    v2 = v2_transformations.create_si_to_uni_dynamics(0.5, 2.0)(dxi, x)
    assert not np.allclose(v2[1], dxu[1])  # V2 turns by atan2(across, along)


def test_backwards_motion_is_the_forward_law_in_classic(states) -> None:
    x, goals = states
    classic = classic_transformations.create_si_to_uni_dynamics_with_backwards_motion()(goals[:2], x)
    np.testing.assert_array_equal(classic, classic_transformations.create_si_to_uni_dynamics()(goals[:2], x))
    behind = np.cos(x[2]) * goals[0] + np.sin(x[2]) * goals[1] < 0
    assert behind.any() and np.all(classic[0, behind] < 0)
    v2 = v2_transformations.create_si_to_uni_dynamics_with_backwards_motion()(goals[:2], x)
    assert not np.allclose(v2[1, behind], classic[1, behind])  # V2 turns the back of the robot to the command


def test_si_to_uni_mapping_clips_omega(states) -> None:
    x, goals = states
    dxi = goals[:2]
    si_to_uni, uni_to_si_states = classic_transformations.create_si_to_uni_mapping(projection_distance=0.05)
    c, s = np.cos(x[2]), np.sin(x[2])
    omega = (-s * dxi[0] + c * dxi[1]) / 0.05
    assert np.any(np.abs(omega) > np.pi)  # the pin means something: some commands are clipped
    np.testing.assert_allclose(si_to_uni(dxi, x), [c * dxi[0] + s * dxi[1], np.clip(omega, -np.pi, np.pi)])
    np.testing.assert_allclose(v2_transformations.create_si_to_uni_mapping()[0](dxi, x)[1], omega)  # V2: no clip
    np.testing.assert_allclose(uni_to_si_states(x), x[:2] + 0.05 * np.vstack([c, s]))
    dxu = goals[:2]
    back = classic_transformations.create_uni_to_si_dynamics(projection_distance=0.05)(dxu, x)
    np.testing.assert_allclose(back, [c * dxu[0] - 0.05 * s * dxu[1], s * dxu[0] + 0.05 * c * dxu[1]])
