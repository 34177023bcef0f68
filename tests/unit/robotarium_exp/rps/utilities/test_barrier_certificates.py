"""Barrier certificates: constraints hold, the solution equals an independent QP, failures are counted."""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest

import robotarium_exp.rps.utilities.barrier_certificates as bc
import robotarium_exp.rps_classic.utilities.barrier_certificates as classic
from robotarium_exp.rps.errors import RobotariumError
from robotarium_exp.rps.utilities.barrier_certificates import _solve_qp
from unicycle_mapping import si_to_uni, uni_to_si, uni_to_si_states

TIGHT = {'tol_gap_abs': 1e-12, 'tol_gap_rel': 1e-12, 'tol_feas': 1e-12, 'tol_ktratio': 1e-10}


def tight_configuration(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    side = int(np.ceil(np.sqrt(n)))
    k = np.arange(n)
    x = np.vstack([(k % side) * 0.19 - 0.9, (k // side) * 0.19 - 0.6]) + 0.02 * rng.standard_normal((2, n))
    return x, rng.normal(0.0, 0.15, (2, n))


def reference(u_hat: np.ndarray, x: np.ndarray, spec: bc.BarrierSpec) -> np.ndarray | None:
    """The same QP with every row (no pruning), written with cvxpy and solved by Clarabel to 1e-12.

    V2's speed polygon, written out here: side k has outward normal at angle 2 pi k / 8 and sits at the limit
    times cos(pi/8), except the first one of the plain certificates, at the limit.
    """
    a, b = bc.barrier_rows(x, bc.BarrierSpec(spec.safety_radius, spec.barrier_gain, 1e9, spec.boundary, False))
    u = cp.Variable(u_hat.size)
    constraints = [a @ u <= b]
    if spec.speed_polygon:
        for k in range(8):
            normal = np.array([np.cos(2 * np.pi * k / 8), np.sin(2 * np.pi * k / 8)])
            bound = spec.magnitude_limit * (1.0 if k == 0 and spec.full_first_side else np.cos(np.pi / 8))
            for robot in range(x.shape[1]):
                constraints.append(normal @ u[2 * robot : 2 * robot + 2] <= bound)
    problem = cp.Problem(cp.Minimize(cp.sum_squares(u - u_hat.reshape(-1, order='F'))), constraints)
    problem.solve(solver=cp.CLARABEL, **TIGHT)
    if problem.status != cp.OPTIMAL:
        return None
    assert u.value is not None  # an optimal solve sets the variable
    return u.value.reshape(2, -1, order='F')


@pytest.mark.usefixtures('exact_qp')
def test_tight_configurations_against_an_independent_qp() -> None:
    """Twelve tight configurations of 6 to 20 robots: every row holds, the answer is the reference optimum."""
    rng = np.random.default_rng(0)
    certificate = bc.create_si_barrier_certificate_with_boundary()
    worst_violation = worst_difference = 0.0
    checked = 0
    for _ in range(12):
        n = int(rng.integers(6, 21))
        x, u_hat = tight_configuration(rng, n)
        safe = certificate(u_hat, x)
        expected = reference(u_hat, x, certificate.spec)
        if expected is None:
            continue
        all_rows, all_rhs = bc.barrier_rows(x, bc.BarrierSpec(0.15, 100.0, 1e9, (-1.7, 1.7, -1.1, 1.1), False))
        worst_violation = max(worst_violation, float((all_rows @ safe.reshape(-1, order='F') - all_rhs).max()))
        worst_difference = max(worst_difference, float(np.abs(safe - expected).max()))
        checked += 1
    assert checked >= 11 and certificate.stats.failures == 12 - checked
    assert worst_violation <= 1e-9  # every pairwise and boundary row, pruned or not
    assert worst_difference <= 1e-6


@pytest.mark.usefixtures('exact_qp')
def test_feasible_commands_pass_unchanged_and_far_pairs_are_pruned() -> None:
    x = np.array([[0.0, 1.0, -1.0], [0.0, 0.5, -0.5]])
    u = np.array([[0.05, -0.05, 0.0], [0.0, 0.02, 0.1]])
    certificate = bc.create_si_barrier_certificate()
    np.testing.assert_array_equal(certificate(u, x), u)
    rows = bc.bounded_barrier_rows(x, certificate.spec)
    assert rows.a.shape[0] == 2 * 3  # the diagonal sides; no pair row: all farther than a row can bind from


@pytest.mark.usefixtures('exact_qp')
def test_infeasible_state_is_counted_warned_and_zeroed() -> None:
    certificate = classic.create_single_integrator_barrier_certificate_with_boundary()
    x = np.array([[1.59], [0.0]])  # inside the wall band: a command towards the wall is turned back
    u = certificate(np.array([[0.2], [0.0]]), x)
    assert u[0, 0] < 0.0
    impossible = bc.create_si_barrier_certificate(magnitude_limit=0.01)
    x2 = np.array([[0.0, 0.01], [0.0, 0.0]])  # 1 cm apart: separating needs 0.056 m/s, the limit allows 0.02
    with pytest.warns(RuntimeWarning, match='QP failed. Commanding zero velocities'):
        zeros = impossible(np.zeros((2, 2)), x2)
    np.testing.assert_array_equal(zeros, 0.0)
    assert impossible.stats.failures == 1 and impossible.stats.solves == 1


def test_generation_names_and_defaults() -> None:
    assert bc.create_si_barrier_certificate().spec.safety_radius == 0.15
    assert classic.create_single_integrator_barrier_certificate().spec.safety_radius == 0.17
    assert not classic.create_single_integrator_barrier_certificate().spec.speed_polygon
    uni_v2 = bc.create_uni_barrier_certificate_with_boundary()
    assert uni_v2.inner.spec.safety_radius == pytest.approx(0.12 + 2 * 0.03)
    assert classic.create_unicycle_barrier_certificate().inner.spec.safety_radius == pytest.approx(0.12 + 0.05)


def test_unicycle_certificate_keeps_projection_points_apart() -> None:
    rng = np.random.default_rng(5)
    certificate = bc.create_uni_barrier_certificate()
    poses = np.array([[0.0, 0.3], [0.0, 0.0], [0.0, np.pi]])  # facing each other
    dxu = np.array([[0.2, 0.2], [0.0, 0.0]])
    for _ in range(200):
        safe = certificate(dxu + 0.01 * rng.standard_normal((2, 2)), poses)
        poses = poses + 0.033 * np.vstack([safe[0] * np.cos(poses[2]), safe[0] * np.sin(poses[2]), safe[1]])
    points = uni_to_si_states(poses, 0.05)
    assert np.hypot(*(points[:, 0] - points[:, 1])) >= 0.25 - 1e-3


def test_certificates_fail_where_v2_fails_with_v2s_error() -> None:
    certificate = bc.create_si_barrier_certificate()
    with pytest.raises(IndexError, match='index 2 is out of bounds for axis 1 with size 2'):
        certificate(np.zeros((2, 3)), np.zeros((2, 2)))  # V2 reads x's columns for every command's column
    with pytest.raises(AttributeError, match="'list' object has no attribute 'shape'"):
        certificate([[0.1, 0.0], [0.0, 0.0]], np.zeros((2, 2)))
    with pytest.raises(TypeError, match=r"unsupported operand type\(s\) for \*\* or pow\(\): 'str' and 'int'"):
        bc.create_si_barrier_certificate(safety_radius='a')(np.zeros((2, 2)), np.eye(2))
    with pytest.raises(AssertionError, match='states must be 3xN. Got 2x2.'):
        bc.create_uni_barrier_certificate()(np.zeros((2, 2)), np.eye(2))  # V2's map checks the poses


@pytest.mark.usefixtures('exact_qp')
@pytest.mark.parametrize('gain', [-1, 1])
def test_a_gain_v2_accepts_is_used_as_given(gain: int) -> None:
    """V2 builds a certificate of any gain, a negative one too, and solves with it: the exact projection of two
    robots 0.2 m apart, driving apart, on the pair row 0.4 (u_0x - u_1x) <= gamma h^3."""
    x, dxi = np.array([[0.0, 0.2], [0.0, 0.0]]), np.array([[0.15, -0.15], [0.0, 0.02]])
    bound = gain * (0.2**2 - 0.15**2) ** 3 / 0.4
    gap = dxi[0, 0] - dxi[0, 1] - bound  # how far the nominal command violates u_0x - u_1x <= bound
    expected = dxi - [[gap / 2, -gap / 2], [0.0, 0.0]]
    np.testing.assert_allclose(bc.create_si_barrier_certificate(barrier_gain=gain)(dxi, x), expected, atol=1e-12)


@pytest.mark.usefixtures('exact_qp')
def test_v2_semantics_lone_robot_polygon_sides_and_obstacles() -> None:
    """A lone robot's command passes (V2 returns it before any QP); a command over the limit is cut by the
    polygon, not pre-scaled: the +x side sits at the limit in the plain certificate, at limit cos(pi/8) with walls."""
    lone = np.array([[0.5], [0.0]])
    np.testing.assert_array_equal(bc.create_si_barrier_certificate()(lone, np.zeros((2, 1))), lone)
    far = np.array([[0.0, 1.0], [0.0, 0.0]])
    fast = np.array([[0.5, 0.0], [0.0, 0.0]])
    plain = bc.create_si_barrier_certificate()(fast, far)
    walled = bc.create_si_barrier_certificate_with_boundary()(fast, far)
    np.testing.assert_allclose(plain[:, 0], [0.2, 0.0], atol=1e-9)
    np.testing.assert_allclose(walled[:, 0], [0.2 * np.cos(np.pi / 8), 0.0], atol=1e-9)
    diagonal = np.array([[0.5, 0.0], [0.5, 0.0]])  # projected onto the 45-degree side, not scaled along itself
    np.testing.assert_allclose(
        bc.create_si_barrier_certificate()(diagonal, far)[:, 0], [0.2 * np.cos(np.pi / 8) / np.sqrt(2)] * 2, atol=1e-9
    )
    # obstacles: points the unicycles keep clear of, as agents of the QP (V2's third argument)
    certificate = bc.create_uni_barrier_certificate_with_boundary()
    poses = np.array([[0.0, -1.0], [0.0, 0.5], [0.0, 0.0]])
    ahead = np.array([[0.2, 0.0], [0.0, 0.0]])
    obstacle = np.array([[0.03 + 0.19], [0.0]])  # 0.19 m ahead of robot 0's projection point: inside the 0.18 m band
    free = certificate(ahead, poses)
    blocked = certificate(ahead, poses, obstacle)
    assert free[0, 0] == pytest.approx(0.2 * np.cos(np.pi / 8), abs=1e-9)
    # V2 makes obstacle points agents of the QP with zero nominal speed, so they "give way" too: robot 0 and the
    # point share the barrier, u_0 - u_obstacle <= c, and robot 0 keeps (0.2 + c) / 2 of its 0.2 m/s
    c = 150.0 * (0.19**2 - 0.18**2) ** 3 / (2 * 0.19)
    assert blocked[0, 0] == pytest.approx((0.2 + c) / 2, abs=1e-9)
    np.testing.assert_allclose(blocked[:, 1], free[:, 1], atol=1e-9)  # robot 1 is far from it
    assert blocked.shape == (2, 2)  # the obstacle's own column is dropped


# ---------------------------------------------------------------------- the testbed's solver (the default)


def v2_rows(points: np.ndarray, radius: float, gain: float, limit: float) -> tuple[np.ndarray, np.ndarray]:
    """V2's plain certificate's rows as its source lays them out: each pair (i < j) in turn, then each robot's
    eight polygon sides, counter-clockwise from +x; the first at the limit, the others at limit cos(pi/8)."""
    n = points.shape[1]
    rows, rhs = [], []
    for i in range(n):
        for j in range(i + 1, n):
            diff = points[:, i] - points[:, j]
            row = np.zeros(2 * n)
            row[2 * i : 2 * i + 2], row[2 * j : 2 * j + 2] = -2 * diff, 2 * diff
            rows.append(row)
            rhs.append(gain * (diff @ diff - radius**2) ** 3)
    for i in range(n):
        for k in range(8):
            row = np.zeros(2 * n)
            row[2 * i : 2 * i + 2] = np.cos(k * np.pi / 4), np.sin(k * np.pi / 4)
            rows.append(row)
            rhs.append(limit if k == 0 else limit * np.cos(np.pi / 8))
    return np.array(rows), np.array(rhs)


def v2_boundary_rows(x: np.ndarray, radius: float, gain: float, limit: float, walls: tuple) -> tuple:
    """V2's boundary certificate's rows written out as its source builds them, loop by loop: the pairs i < j, then
    robot by robot its four walls (+y, -y, +x, -x), then robot by robot its eight sides, with V2's coefficients
    (0, 1 and 1/sqrt(2)), all at limit cos(pi/8)."""
    n, diagonal = x.shape[1], 1 / np.sqrt(2)
    rows, rhs = [], []
    for i in range(n - 1):
        for j in range(i + 1, n):
            diff = x[:, i] - x[:, j]
            row = np.zeros(2 * n)
            row[2 * i : 2 * i + 2], row[2 * j : 2 * j + 2] = -2 * diff, 2 * diff
            rows.append(row)
            rhs.append(gain * (np.dot(diff, diff) - radius**2) ** 3)
    xmin, xmax, ymin, ymax = walls
    for k in range(n):
        room = (ymax - radius / 2 - x[1, k], x[1, k] - ymin - radius / 2, xmax - radius / 2 - x[0, k])
        for normal, distance in zip(([0, 1], [0, -1], [1, 0], [-1, 0]), (*room, x[0, k] - xmin - radius / 2)):
            row = np.zeros(2 * n)
            row[2 * k : 2 * k + 2] = normal
            rows.append(row)
            rhs.append(0.4 * gain * distance**3)
    sides = ([1, 0], [diagonal, diagonal], [0, 1], [-diagonal, diagonal])
    for i in range(n):
        for normal in (*sides, *([-c for c in side] for side in sides)):
            row = np.zeros(2 * n)
            row[2 * i : 2 * i + 2] = normal
            rows.append(row)
            rhs.append(limit * np.cos(np.pi / 8))
    return np.array(rows), np.array(rhs)


def test_the_rows_are_v2s_row_for_row_so_the_testbed_qp_is_v2s() -> None:
    """The same rows in the same order with the same coefficients, bit for bit (the walls' bounds to rounding: V2
    subtracts the wall and R/2 from each position, ours adds the position to their precomputed sum): cvxopt, stopped
    early, answers V2's point (its answer to an infeasible QP, two robots at one point, depends on the order)."""
    rng = np.random.default_rng(8)
    for n in (2, 3, 7):
        x = rng.uniform(-1.0, 1.0, (2, n))
        certificate = bc.create_si_barrier_certificate_with_boundary(boundary_points=np.array([-1.6, 1.6, -1.0, 1.0]))
        spec = certificate.spec
        a, b = bc.barrier_rows(x, spec)
        expected_a, expected_b = v2_boundary_rows(x, 0.15, 100.0, 0.2, (-1.6, 1.6, -1.0, 1.0))
        np.testing.assert_array_equal(a, expected_a)
        np.testing.assert_allclose(b, expected_b, rtol=1e-12, atol=0)


def test_testbed_solver_answers_what_cvxopt_at_the_testbed_options_answers() -> None:
    """The default certificate equals cvxopt run by hand on V2's own row layout, at V2's options."""
    from cvxopt import matrix, solvers

    assert bc.qp_solver() == 'testbed'
    rng = np.random.default_rng(4)
    certificate = bc.create_uni_barrier_certificate()
    worst = 0.0
    for _ in range(30):
        n = int(rng.integers(2, 12))
        x = np.vstack([rng.uniform(-0.5, 0.5, (2, n)), rng.uniform(-np.pi, np.pi, n)])
        dxu = np.vstack([rng.uniform(-0.2, 0.2, n), rng.uniform(-3.0, 3.0, n)])
        points, dxi = uni_to_si_states(x, 0.05), uni_to_si(dxu, x, 0.05)
        a, b = v2_rows(points, 0.25, 100.0, 0.2)
        options = {'show_progress': False, 'reltol': 1e-2, 'feastol': 1e-2, 'maxiters': 50}
        solution = solvers.qp(
            matrix(2.0 * np.eye(2 * n)),
            matrix(-2.0 * dxi.reshape(-1, order='F')),
            matrix(a),
            matrix(b),
            options=options,
        )
        assert solution['status'] == 'optimal'
        by_hand = si_to_uni(np.array(solution['x']).reshape(2, n, order='F'), x, 0.05)
        worst = max(worst, float(np.abs(certificate(dxu, x) - by_hand).max()))
    assert worst <= 1e-9


def test_testbed_answers_are_strictly_feasible_and_near_the_optimum() -> None:
    """cvxopt stops early from the inside: every row holds, the answer within 0.02 m/s of the exact optimum."""
    rng = np.random.default_rng(5)
    certificate = bc.create_si_barrier_certificate_with_boundary()
    worst_violation, worst_gap = -np.inf, 0.0
    for _ in range(40):
        x, u_hat = tight_configuration(rng, int(rng.integers(6, 21)))
        testbed = certificate(u_hat, x)
        previous = bc.use_qp_solver('exact')
        try:
            exact = certificate(u_hat, x)
        finally:
            bc.use_qp_solver(previous)
        a, b = bc.barrier_rows(x, certificate.spec)
        worst_violation = max(worst_violation, float((a @ testbed.reshape(-1, order='F') - b).max()))
        worst_gap = max(worst_gap, float(np.abs(testbed - exact).max()))
    assert certificate.stats.failures == 0
    assert worst_violation <= 0.0
    assert 1e-5 < worst_gap <= 0.02  # not the optimum, but near it


def test_unknown_qp_solver_is_refused_by_name() -> None:
    with pytest.raises(RobotariumError, match="unknown QP solver 'osqp'; choose one of testbed, exact"):
        bc.use_qp_solver('osqp')
    assert bc.qp_solver() == 'testbed'


# ---------------------------------------------------------------------- the exact solver's warm starts


def cold_answer(certificate: bc.Certificate, u_hat: np.ndarray, x: np.ndarray) -> np.ndarray | None:
    a, b = bc.barrier_rows(x, certificate.spec)
    u = bc.least_distance(u_hat.reshape(-1, order='F'), a, b)
    return None if u is None else u.reshape(2, -1, order='F')


@pytest.mark.usefixtures('exact_qp')
def test_warm_started_certificate_equals_the_cold_solve_along_trajectories_and_jumps() -> None:
    """Along trajectories (the active set kept or changed by a few rows), and after jumps to unrelated states
    (a stale seed), the certificate answers what DAQP from scratch answers; the seeded paths are taken."""
    rng = np.random.default_rng(7)
    taken = {'seeded': 0}
    warm_least_distance = bc.warm_least_distance

    def counting(
        u_hat: np.ndarray, rows: bc.BoundedRows, seed: np.ndarray, sides: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        taken['seeded'] += seed.size > 0
        return warm_least_distance(u_hat, rows, seed, sides)

    bc.warm_least_distance = counting
    try:
        worst = 0.0
        for n in (4, 9, 16):
            certificate = bc.create_si_barrier_certificate_with_boundary()
            x, _ = tight_configuration(rng, n)
            for step in range(60):
                if step % 20 == 19:  # a jump: the last active rows belong to another state
                    x, _ = tight_configuration(rng, n)
                u_hat = 0.15 * (-x - 0.3 * x.mean(axis=1, keepdims=True)) / 0.5 + 0.01 * rng.standard_normal((2, n))
                safe = certificate(u_hat, x)
                expected = cold_answer(certificate, u_hat, x)
                assert expected is not None
                worst = max(worst, float(np.abs(safe - expected).max()))
                x = x + 0.033 * safe
            assert certificate.stats.failures == 0
    finally:
        bc.warm_least_distance = warm_least_distance
    assert worst <= 1e-9
    assert taken['seeded'] > 60


def test_warm_least_distance_from_right_wrong_and_no_seeds() -> None:
    """The exact answer (that of DAQP on every row, unfolded) and its active rows at their sides, whatever the
    seed: the true active rows, half of them, others at random sides, none."""
    rng = np.random.default_rng(3)
    spec = bc.create_si_barrier_certificate_with_boundary().spec
    none = np.zeros(0, dtype=np.intp)
    checked = 0
    for _ in range(40):
        x, u_hat = tight_configuration(rng, int(rng.integers(3, 13)))
        x[0, 0] = 1.45  # near the +x wall
        flat = u_hat.ravel()  # the bounded rows' order: component by component
        expected = bc.least_distance(u_hat.ravel(order='F'), *bc.barrier_rows(x, spec))
        if expected is None:
            continue
        expected = expected.reshape(-1, 2).T.ravel()
        rows = bc.bounded_barrier_rows(x, spec)
        _, active, lam = bc.warm_least_distance(flat, rows, none, none) or (None, None, None)
        assert active is not None and lam is not None
        at = np.where(lam > 0, rows.upper[active], rows.lower[active])
        assert np.all(np.abs(rows.apply(expected)[active] - at) <= 1e-9)
        sides = np.where(lam > 0, 1, -1)
        others = np.sort(rng.choice(rows.keys.size, 5, replace=False))
        seeds = ((active, sides), (active[::2], sides[::2]), (others, rng.choice([-1, 1], 5)))
        for seed, seed_sides in seeds:
            solved = bc.warm_least_distance(flat, rows, seed, seed_sides)
            assert solved is not None
            np.testing.assert_allclose(solved[0], expected, atol=1e-9)
            np.testing.assert_array_equal(solved[1], active)
            np.testing.assert_array_equal(np.sign(solved[2]), np.sign(lam))
        checked += 1
    assert checked >= 30


def one_sided(a: np.ndarray, b: np.ndarray) -> bc.BoundedRows:
    return bc.BoundedRows(a, np.full(b.size, -np.inf), b, np.arange(b.size))


def test_warm_least_distance_trivial_projection_corner_two_sided_and_infeasible() -> None:
    rows = one_sided(np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]), np.array([1.0, 1.0, 1.5]))
    none = np.zeros(0, dtype=np.intp)
    u, active, _ = bc.warm_least_distance(np.array([0.5, 0.5]), rows, none, none) or (None, None, None)
    np.testing.assert_array_equal(u, [0.5, 0.5])  # feasible: unchanged, nothing active
    assert active is not None and active.size == 0
    u, active, _ = bc.warm_least_distance(np.array([2.0, 0.0]), rows, none, none) or (None, None, None)
    np.testing.assert_allclose(u, [1.0, 0.0], atol=1e-15)  # one row violated: the projection onto it
    np.testing.assert_array_equal(active, [0])
    u, active, _ = bc.warm_least_distance(np.array([2.0, 2.0]), rows, none, none) or (None, None, None)
    np.testing.assert_allclose(u, [0.75, 0.75], atol=1e-15)  # three violated; only the diagonal binds
    np.testing.assert_array_equal(active, [2])
    u, active, _ = bc.warm_least_distance(np.array([2.0, 0.9]), rows, none, none) or (None, None, None)
    np.testing.assert_allclose(u, [1.0, 0.5], atol=1e-15)  # two violated, both bind: the corner
    np.testing.assert_array_equal(active, [0, 2])
    # two-sided: the component bounds -1 <= u_x <= 1, 0 <= u_y <= 2 and -1 <= u_x - u_y <= 1
    box = bc.BoundedRows(np.array([[1.0, -1.0]]), np.array([-1.0, 0.0, -1.0]), np.array([1.0, 2.0, 1.0]), none)
    u, active, lam = bc.warm_least_distance(np.array([-3.0, 0.5]), box, none, none) or (None, None, None)
    np.testing.assert_allclose(u, [-1.0, 0.0], atol=1e-15)  # u_x and u_x - u_y at their lower bounds
    np.testing.assert_array_equal(active, [0, 2])
    assert lam is not None and np.all(lam < 0.0)
    opposite = one_sided(np.array([[1.0, 0.0], [-1.0, 0.0]]), np.array([-1.0, -1.0]))
    assert bc.warm_least_distance(np.zeros(2), opposite, np.array([0, 1]), np.array([1, 1])) is None


def test_kkt_point_refuses_wrong_signs_violated_rows_and_slack_active_rows() -> None:
    rows = one_sided(np.array([[1.0, 0.0], [0.0, 1.0]]), np.array([1.0, 1.0]))
    u_hat = np.array([2.0, 0.5])
    np.testing.assert_allclose(bc.kkt_point(u_hat, rows, np.array([0]), np.array([1.0])), [1.0, 0.5])
    assert bc.kkt_point(u_hat, rows, np.array([0, 1]), np.array([1.0, -0.5])) is None  # lam < 0, no lower bound
    assert bc.kkt_point(u_hat, rows, np.array([1]), np.array([0.0])) is None  # row 0 violated
    assert bc.kkt_point(u_hat, rows, np.array([0]), np.array([1.5])) is None  # row 0 active but slack
    box = bc.BoundedRows(np.zeros((0, 2)), np.array([-1.0, -1.0]), np.array([1.0, 1.0]), np.arange(2))
    np.testing.assert_allclose(bc.kkt_point(np.array([-3.0, 0.0]), box, np.array([0]), np.array([-2.0])), [-1.0, 0.0])
    assert bc.kkt_point(np.array([-3.0, 0.0]), box, np.array([0]), np.array([-4.0])) is None  # past the upper one


def test_bounded_rows_hold_exactly_where_every_row_holds() -> None:
    """The folded and pruned rows and V2's rows, every one, admit the same commands; a pair row's key names it."""
    rng = np.random.default_rng(2)
    for certificate in (bc.create_si_barrier_certificate_with_boundary(), bc.create_si_barrier_certificate()):
        for trial in range(8):  # tight states, and spread ones: pairs about as far apart as pruning starts
            x = tight_configuration(rng, 12)[0] if trial % 2 else rng.uniform([[-1.5], [-0.9]], [[1.5], [0.9]], (2, 12))
            x[0, 0] = 1.5  # near a wall
            rows = bc.bounded_barrier_rows(x, certificate.spec)
            a, b = bc.barrier_rows(x, certificate.spec)
            assert np.all(np.diff(rows.keys) > 0)
            pairs = rows.keys >= 4 * 12
            by_component = np.r_[0:24:2, 1:24:2]  # the bounded rows' u: all x, then all y
            np.testing.assert_array_equal(rows.a[pairs[24:]], a[rows.keys[pairs] - 4 * 12][:, by_component])
            u = rng.normal(0.0, 0.15, (2000, 24)) * rng.choice([0.0, 0.001, 0.5, 1.0, 2.0], (2000, 1))
            # and each pair heading for each other at the polygon's inner radius, the others still
            i, j = np.triu_indices(12, k=1)
            heading = (x[:, i] - x[:, j]) / np.hypot(*(x[:, i] - x[:, j])) * 0.2 * np.cos(np.pi / 8)
            approach = np.zeros((i.size, 12, 2))
            approach[np.arange(i.size), i], approach[np.arange(i.size), j] = -heading.T, heading.T
            u = np.vstack([u, approach.reshape(i.size, 24)])
            full = np.all(u @ a.T <= b, axis=1)
            values = np.array([rows.apply(command[by_component]) for command in u])
            bounded = np.all((values <= rows.upper) & (values >= rows.lower), axis=1)
            np.testing.assert_array_equal(bounded, full)
            assert 0 < full.sum() < full.size


@pytest.mark.usefixtures('exact_qp')
def test_solve_qp_returns_the_projection_or_none() -> None:
    a = np.array([[1.0, 0.0, 0.0, 0.0]])
    np.testing.assert_allclose(
        _solve_qp(2, np.array([[0.3, 0.1], [0.2, -0.1]]), a, np.array([0.1])), [[0.1, 0.1], [0.2, -0.1]]
    )
    assert _solve_qp(1, np.zeros((2, 1)), np.array([[1.0, 0.0], [-1.0, 0.0]]), np.array([-1.0, -1.0])) is None
