"""The exact unicycle step for constant commands."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from unicycle_mapping.unicycle import unicycle_step


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


def test_the_step_solves_the_unicycle_ode() -> None:
    """Random poses and commands: the step equals an accurate numerical solution; headings are wrapped."""
    rng = np.random.default_rng(11)
    poses = np.vstack([rng.uniform(-1, 1, (2, 6)), rng.uniform(-np.pi, np.pi, 6)])
    dxu = np.vstack([rng.uniform(-0.2, 0.2, 6), rng.uniform(-4, 4, 6)])
    dt = 0.7
    end = unicycle_step(poses, dxu, dt)
    for k in range(6):
        v, omega = dxu[:, k]
        sol = solve_ivp(
            lambda _t, p, v=v, omega=omega: [v * math.cos(p[2]), v * math.sin(p[2]), omega],
            (0.0, dt),
            poses[:, k],
            rtol=1e-12,
            atol=1e-13,
            method='DOP853',
        )
        np.testing.assert_allclose(end[:2, k], sol.y[:2, -1], atol=1e-10)
        assert end[2, k] == pytest.approx(np.angle(np.exp(1j * sol.y[2, -1])), abs=1e-10)
    assert np.all((end[2] > -np.pi) & (end[2] <= np.pi))
