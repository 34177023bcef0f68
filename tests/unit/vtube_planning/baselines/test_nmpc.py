"""Distributed NMPC: rollout, cost and wall terms by hand, the casadi problem against numpy, short closed loops."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.baselines.nmpc import (
    NmpcParams,
    NmpcSwarm,
    rollout,
    stage_costs,
    wall_slack,
)
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile


def straight(half_width: float) -> VirtualTube:
    return VirtualTube(ArcPath((ArcPiece(20.0),)), WidthProfile(half_width, (WidthPart('constant', 20.0),)))


# ---------------------------------------------------------------------- NMPC


def test_rollout_is_the_exact_double_integrator() -> None:
    u = np.tile([0.5, -0.2], (4, 1))
    p, v = rollout(np.array([1.0, 2.0]), np.array([3.0, 0.0]), u, 0.25)
    t = 0.25 * np.arange(1, 5)[:, None]
    np.testing.assert_allclose(p, [1.0, 2.0] + [3.0, 0.0] * t + 0.5 * np.array([0.5, -0.2]) * t**2, atol=1e-12)
    np.testing.assert_allclose(v, [3.0, 0.0] + np.array([0.5, -0.2]) * t, atol=1e-12)


def test_cost_terms_for_two_robots_by_hand() -> None:
    params = NmpcParams(horizon=1, dt_s=1.0, v_ref=5.0, d_ref=1.0)
    p, v = rollout(np.zeros(2), np.array([3.0, 4.0]), np.zeros((1, 2)), 1.0)  # at (3, 4) moving at (3, 4)
    other = np.array([[[3.0, 5.5]]])  # the neighbour's prediction, 1.5 m away
    costs = stage_costs(p, v, np.zeros((1, 2)), other, np.array([1.0, 0.0]), params)
    assert costs['separation'] == pytest.approx((1.5**2 - 1.0) ** 2)  # W_sep 1, one neighbour
    assert costs['direction'] == pytest.approx((1 - 9 / 25) ** 2)  # 3 of |v| = 5 along the tangent
    assert costs['navigation'] == pytest.approx(2.0**2 * (25 - 25) ** 2)
    assert costs['effort'] == 0.0


def test_wall_constraint_by_hand() -> None:
    # a straight tube of half-width 1 along x, margin 0.4: room 0.6 on each side of the centre line
    p = np.array([[3.0, 0.8], [4.0, -0.1]])
    foot = np.array([[3.0, 0.0], [4.0, 0.0]])
    normal = np.array([[0.0, 1.0], [0.0, 1.0]])
    slack = wall_slack(p, foot, normal, np.array([0.6, 0.6]))
    np.testing.assert_allclose(slack, [0.6 - 0.8, 0.6 + 0.1, 0.6 + 0.8, 0.6 - 0.1])  # the first is violated


def test_the_casadi_problem_is_the_numpy_cost_and_constraints() -> None:
    """The NLP IPOPT solves, evaluated at random points, equals stage_costs, wall_slack and the separation."""
    from vtube_planning.baselines.nmpc import AgentProblem

    params = NmpcParams()
    tube = straight(2.0)
    problem = AgentProblem(params, 3)
    rng = np.random.default_rng(0)
    h = params.horizon
    for _ in range(5):
        p0, v0 = rng.normal(size=2) + [3.0, 0.0], rng.normal(size=2) + [2.0, 0.0]
        others, tangent = rng.normal(size=(3, h, 2)) + [3.0, 0.0], np.array([0.6, 0.8])
        u = rng.normal(size=(h, 2))
        p, v = rollout(p0, v0, u, params.dt_s)
        walls = tube.project(p.T + 0.1)
        f, g = problem.terms(u.ravel(), problem.pack(p0, v0, tangent, others, walls, params.wall_margin))
        assert float(f) == pytest.approx(sum(stage_costs(p, v, u, others, tangent, params).values()), rel=1e-10)
        room = walls.half_width_m - params.wall_margin
        separation = (np.sum((others - p[None]) ** 2, axis=2) - params.d_safe**2).ravel()
        expected = np.concatenate([wall_slack(p, walls.foot_m.T, walls.normal.T, room), separation])
        np.testing.assert_allclose(np.asarray(g).ravel(), expected, rtol=1e-10, atol=1e-12)


def test_nmpc_converges_and_never_applies_a_failed_solve() -> None:
    tube = straight(2.0)
    swarm = NmpcSwarm(tube, NmpcParams(v_max=2.0, v_ref=2.0, d_safe=0.8, d_ref=1.6))
    positions = np.array([[1.0, 1.0, 3.0], [0.6, -0.6, 0.0]])
    velocities = np.tile([[1.5], [0.0]], 3)
    for _ in range(20):
        velocities = swarm.command(positions, velocities, tube.project(positions), 0.05)
        positions = positions + 0.05 * velocities
    assert swarm.solves == 3 * 10 and swarm.converged == swarm.solves and swarm.fallbacks == 0
    assert swarm.softened == 0  # room for everyone: no constraint had to give
    # two agents already closer than d_safe: the constraint is softened (and counted), the solve still converges
    tight = NmpcSwarm(tube, NmpcParams(v_max=2.0, v_ref=2.0, d_safe=0.8))
    positions = np.array([[1.0, 1.2], [0.0, 0.0]])
    tight.command(positions, np.zeros((2, 2)), tube.project(positions), 0.05)
    assert tight.converged == tight.solves == 2 and tight.softened == 2
    # a solve that does not converge (here: one iteration allowed) is not applied: the last converged plan is
    stopped = NmpcSwarm(tube, NmpcParams(v_max=2.0, v_ref=2.0, max_iter=1))
    stopped.command(positions, np.ones((2, 2)), tube.project(positions), 0.05)
    assert stopped.fallbacks == stopped.solves == 2 and stopped.converged == 0
    assert np.all(stopped.held == 0.0)  # no converged plan yet: zero acceleration, not IPOPT's iterate


def test_nmpc_respects_the_linearised_wall_and_drives_along_the_tube() -> None:
    tube = straight(1.0)
    swarm = NmpcSwarm(tube, NmpcParams(v_max=2.0, v_ref=2.0, wall_margin=0.3))
    positions = np.array([[2.0, 2.0], [0.6, -0.6]])  # 0.4 m from the walls, inside the margin band's reach
    velocities = np.array([[1.0, 1.0], [0.5, -0.5]])  # heading out, towards the walls
    for _ in range(40):
        command = swarm.command(positions, velocities, tube.project(positions), 0.05)
        velocities = command
        positions = positions + 0.05 * command
    assert np.all(np.abs(positions[1]) <= 1.0)  # still inside the tube
    assert np.all(velocities[0] > 1.0)  # moving along it
    assert np.all(np.hypot(*velocities) <= 2.0 + 1e-9)  # capped at v_max
    assert swarm.solves == 2 * 20  # every 0.1 s, each agent
