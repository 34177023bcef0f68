"""The tube experiment's safety filter: the exact least-distance solver, the band rows, safety before the band."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.flight import walls
from robotarium_exp.rps.utilities.barrier_certificates import least_distance
from robotarium_exp.rps.utilities.barrier_rows import BarrierSpec, barrier_rows
from robotarium_exp.safety import EXIT_KEEP_M, WALL_GAIN_PER_S, WALL_KEEP_M, SafetyFilter, least_distance_nnls
from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile

BARRIER = BarrierSpec(0.2, 100.0, 0.12, ROBOTARIUM.arena_m, False)


def safety_filter() -> SafetyFilter:
    return SafetyFilter(BARRIER, 0.04, 0.12, 0.05, ROBOTARIUM.base_length_m, ROBOTARIUM.max_linear_speed_mps)


def test_nnls_least_distance_equals_daqp_on_random_barrier_problems() -> None:
    """Two independent exact solvers (NNLS on the least-distance dual, DAQP's active set) agree."""
    rng = np.random.default_rng(5)
    solved = 0
    for _ in range(150):
        n = int(rng.integers(2, 9))
        x = rng.uniform(-0.6, 0.6, (2, n))
        u_hat = rng.uniform(-0.15, 0.15, 2 * n)
        a, b = barrier_rows(x, BARRIER)
        mine, reference = least_distance_nnls(u_hat, a, b), least_distance(u_hat, a, b)
        assert (mine is None) == (reference is None)
        if mine is not None and reference is not None:
            np.testing.assert_allclose(mine, reference, atol=1e-7)
            assert np.all(a @ mine - b <= 1e-7 * np.maximum(1.0, np.abs(a).max(axis=1)))
            solved += 1
    assert solved > 100


def test_infeasible_rows_are_reported_not_approximated() -> None:
    a = np.array([[1.0, 0.0], [-1.0, 0.0]])
    assert least_distance_nnls(np.zeros(2), a, np.array([-1.0, -1.0])) is None  # u_x <= -1 and u_x >= 1
    np.testing.assert_allclose(least_distance_nnls(np.array([2.0, 3.0]), a, np.array([1.0, 5.0])), [1.0, 3.0])


def test_the_band_and_the_wheels_hold_for_flying_robots() -> None:
    """Robots far apart, asked to stop, to rush sideways and to turn: each gets the nearest command in the band."""
    f = safety_filter()
    poses = np.array([[-1.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.5, -0.3]])
    points = poses[:2] + 0.05 * np.vstack([np.cos(poses[2]), np.sin(poses[2])])
    u_hat = np.array([[0.0, 0.3, 0.02], [0.0, 0.0, 0.2]])
    u, held = f(u_hat, poses, points, np.ones(3, dtype=bool))
    assert held
    e = np.vstack([np.cos(poses[2]), np.sin(poses[2])])
    e_perp = np.vstack([-e[1], e[0]])
    v, lateral = np.einsum('in,in->n', e, u), np.einsum('in,in->n', e_perp, u)
    assert np.all(v >= 0.04 - 1e-9) and np.all(v <= 0.12 + 1e-9)
    assert np.all(np.abs(lateral) <= f.lateral_max + 1e-9)
    np.testing.assert_allclose(u[:, 0], [0.04, 0.0], atol=1e-9)  # stop -> v_min straight on
    # too fast and too far sideways: v_max, and the lateral limit the wheels leave at v_max
    np.testing.assert_allclose([v[1], lateral[1]], [0.12, -f.lateral_max], atol=1e-9)
    wheels = v + 0.5 * ROBOTARIUM.base_length_m * np.abs(lateral / 0.05)
    assert np.all(wheels <= ROBOTARIUM.max_linear_speed_mps + 1e-9)  # realisable without wheel saturation


def test_safety_wins_over_the_band_and_is_counted() -> None:
    """Two robots nose to nose at the barrier distance cannot both keep v >= v_min: the band is dropped."""
    f = safety_filter()
    poses = np.array([[-0.15, 0.15], [0.0, 0.0], [0.0, np.pi]])
    points = poses[:2] + 0.05 * np.vstack([np.cos(poses[2]), np.sin(poses[2])])
    u, held = f(np.array([[0.1, -0.1], [0.0, 0.0]]), poses, points, np.ones(2, dtype=bool))
    assert not held and f.stats.band_dropped == 1 and f.stats.failures == 0
    a, b = barrier_rows(points, BARRIER)
    assert np.all(a @ u.reshape(-1, order='F') <= b + 1e-9)  # safe
    assert f.stats.intervention_mps > 0.15


def test_when_the_band_cannot_hold_the_walls_still_do_and_go_only_when_the_robots_need_it() -> None:
    """A robot headed straight into a wall 0.01 m inside what the rows keep: the band (forward at >= v_min, i.e.
    towards the wall) and the wall row (away at >= 0.01 m/s) cannot hold together; the band goes, the wall row
    stays: the robot backs off at WALL_GAIN_PER_S x 0.01 m/s. Two robots nose to nose at the barrier distance
    beside walls that close in on both: the barrier and the walls cannot hold together either, the walls go too."""
    f = safety_filter()
    poses = np.array([[0.0], [0.0], [np.pi / 2]])
    points = poses[:2] + 0.05 * np.vstack([np.cos(poses[2]), np.sin(poses[2])])
    u, held = f(
        np.array([[0.0], [0.1]]), poses, points, np.ones(1, dtype=bool), (np.array([[0.0], [1.0]]), np.array([-0.01]))
    )
    assert not held and f.stats.band_dropped == 1
    np.testing.assert_allclose(u[:, 0], [0.0, -WALL_GAIN_PER_S * 0.01], atol=1e-9)
    poses = np.array([[-0.15, 0.15], [0.0, 0.0], [0.0, np.pi]])
    points = poses[:2] + 0.05 * np.vstack([np.cos(poses[2]), np.sin(poses[2])])
    closing = (np.array([[-1.0, 1.0], [0.0, 0.0]]), np.array([-0.05, -0.05]))  # each must move towards the other
    u, held = f(np.array([[0.1, -0.1], [0.0, 0.0]]), poses, points, np.ones(2, dtype=bool), closing)
    a, b = barrier_rows(points, BARRIER)
    assert not held and f.stats.failures == 0 and np.all(a @ u.reshape(-1, order='F') <= b + 1e-9)
    assert np.any(np.einsum('in,in->n', closing[0], u) > WALL_GAIN_PER_S * closing[1] + 1e-6)  # the walls went


def test_a_wall_row_slows_the_approach_to_the_wall_and_no_more() -> None:
    """One robot heading along +x, asked to slide towards a wall above it (outward normal +y) 0.02 m beyond what the
    rows keep: its velocity towards the wall is cut to WALL_GAIN_PER_S x 0.02 m, its forward speed kept; a robot
    with no wall (NaN) and one moving away from its wall are untouched."""
    f = safety_filter()
    poses = np.array([[-1.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    points = poses[:2] + 0.05 * np.vstack([np.cos(poses[2]), np.sin(poses[2])])
    u_hat = np.array([[0.1, 0.1, 0.1], [0.03, 0.03, -0.03]])
    outward = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]])
    room = np.array([0.02, np.nan, 0.02])
    u, held = f(u_hat, poses, points, np.ones(3, dtype=bool), (outward, room))
    assert held
    np.testing.assert_allclose(u[:, 0], [0.1, WALL_GAIN_PER_S * 0.02], atol=1e-9)
    np.testing.assert_allclose(u[:, 1:], u_hat[:, 1:], atol=1e-12)
    closer = f(u_hat, poses, points, np.ones(3, dtype=bool), (outward, np.array([-0.01, np.nan, 0.02])))[0]
    assert closer[1, 0] == pytest.approx(-WALL_GAIN_PER_S * 0.01)  # inside what the row keeps: driven back


def test_the_walls_of_a_flight_are_the_nearer_wall_or_the_exit_line() -> None:
    """walls(): a flying robot inside the tube, its nearer wall (room: clearance less WALL_KEEP_M), and past the
    exit (not yet left for its slot) the walls' extension; a parked robot, the exit line behind it (room: how far
    beyond the exit less EXIT_KEEP_M); a robot before the entrance, none."""
    tube = VirtualTube(ArcPath((ArcPiece(2.0),)), WidthProfile(0.5, (WidthPart('constant', 2.0),)))
    points = np.array([[1.0, 1.0, 2.3, 2.05, -0.2], [0.3, -0.45, 0.1, -0.4, 0.0]])
    flying = np.array([True, True, False, True, True])
    outward, room = walls(tube.project(points), flying)
    np.testing.assert_allclose(outward[:, :4], [[0.0, 0.0, -1.0, 0.0], [1.0, -1.0, 0.0, -1.0]], atol=1e-12)
    expected = [0.2 - WALL_KEEP_M, 0.05 - WALL_KEEP_M, 0.3 - EXIT_KEEP_M, 0.1 - WALL_KEEP_M]
    np.testing.assert_allclose(room[:4], expected, atol=1e-9)
    assert np.isnan(room[4])


def test_a_wall_row_is_the_rate_the_room_changes_at_in_a_narrowing_bend() -> None:
    """Oracle by finite differences: for robots flying a bend that narrows, the room h moves by -eps o . u when
    the control point moves by eps u (the row o . u <= gain h is dh/dt >= -gain h), in both walls' halves; without
    the narrowing's slope the rows miss it (forward flight closes in on the robot)."""
    width = WidthProfile(0.8, (WidthPart('constant', 1.0), WidthPart('linear', 1.5, to_m=0.35, corner_m=0.2)))
    tube = VirtualTube(ArcPath((ArcPiece(1.0), ArcPiece(1.5, radius_m=2.0))), width)
    rng = np.random.default_rng(11)
    l_m = rng.uniform(1.25, 2.25, 40)  # inside the narrowing's straight slope and the bend
    y = rng.uniform(-0.8, 0.8, 40) * np.asarray(tube.half_width(l_m))
    points = (tube.center_at(l_m) + y[:, None] * tube.normal(l_m)).T
    u = rng.uniform(-0.12, 0.12, (2, 40))
    flying = np.ones(40, dtype=bool)
    here = tube.project(points)
    outward, room = walls(here, flying, np.asarray(tube.half_width_slope(here.l_m)))
    eps = 1e-6
    moved = walls(tube.project(points + eps * u), flying)[1]
    np.testing.assert_allclose((moved - room) / eps, -np.einsum('in,in->n', outward, u), atol=1e-4)
    flat = walls(here, flying)[0]
    assert np.abs(np.einsum('in,in->n', flat - outward, u)).max() > 0.03
