"""Classic ``rps.utilities.barrier_certificates2``: the robust barrier certificate on wheel speeds.

For robots with wheel speeds w (left, right) and unicycle commands u = D w (D: r/2, r/2; -r/L, r/L), the certificate
keeps the points p = (x, y) + d (cos theta, sin theta) apart, despite wheel disturbances up to ``disturbance``
(rad/s, each wheel, the corners of a square): for each pair, with h = |p_i - p_j|^2 - R^2 and g_k the gradient of
h with respect to robot k's wheel speeds,

    g_i w_i + g_j w_j + min over disturbances (g_i e_i) + min (g_j e_j) >= -gamma h^3,

where each min is -disturbance (|g_k,1| + |g_k,2|); likewise between each robot and each obstacle point, and, with
walls, p stays inside ``boundary_points`` (rows ``+/- pdot <= 0.4 gamma (room - R/2)^3``, no disturbance), every
wheel within +/- ``wheel_vel_limit``. Among those wheel speeds it picks the ones closest to the request in the
metric (v - v_hat)^2 + d^2 (omega - omega_hat)^2, exactly (classic solves these with quadprog, an exact solver),
by the exact least-distance QP of V2's certificates in the scaled variables (v, d omega). With walls, classic
solves with cvxopt at its loose options instead, and so does ours with the ``'testbed'`` QP solver (the default:
`robotarium_exp.rps.utilities.barrier_certificates.use_qp_solver`), on classic's rows in classic's order.

Classic's implementation prints its solve time at every call (not reproduced) and sizes buffers by
``max_num_robots`` / ``max_num_obstacles`` (not needed here, but their sizes computed, so that a size classic
cannot allocate fails as there). Where quadprog fails, ``create_robust_barriers`` raises its ``ValueError``, as
classic does.
"""

from __future__ import annotations

import warnings
from typing import Any

import cvxopt
import numpy as np
from numpy.typing import NDArray

from robotarium_exp.rps.utilities.barrier_certificates import (
    TESTBED_QP_OPTIONS,
    BarrierStats,
    FloatArray,
    least_distance,
    qp_solver,
)

__all__ = ['RobustCertificate', 'create_robust_barriers']


class RobustCertificate:
    """``certificate(dxu, x, obstacles=np.empty(0)) -> dxu`` (2xN unicycle commands), with ``stats``.

    ``quadprog_errors``: fail as classic's quadprog solve fails (``create_robust_barriers``): ``ValueError`` with
    quadprog's text when the QP is infeasible, or when a projection distance of 0 makes its objective singular;
    otherwise an infeasible QP commands zeros with a warning.
    """

    def __init__(
        self,
        disturbance: float,
        wheel_vel_limit: float,
        base_length: float,
        wheel_radius: float,
        projection_distance: float,
        barrier_gain: float,
        safety_radius: float,
        boundary_points: FloatArray | None,
        *,
        sizes: tuple[Any, Any, int] = (100, 30, 0),
        quadprog_errors: bool = False,
    ) -> None:
        self.wheels_to_uni = np.array(
            [[wheel_radius / 2, wheel_radius / 2], [-wheel_radius / base_length, wheel_radius / base_length]]
        )
        _ = np.dot(np.array([[1, 0], [0, projection_distance]]), self.wheels_to_uni), -disturbance
        obstacles, robots, per_robot = sizes  # classic sizes its matrices for these: their errors at creation
        np.zeros([(robots**2 - robots) // 2 + robots * obstacles + per_robot * robots, 2 * robots], dtype=bool)
        self.max_robots = robots
        self.given = (disturbance, wheel_vel_limit, projection_distance, barrier_gain, safety_radius)
        """The numbers as given, used (and converted) at each call, as classic uses them there."""
        self.disturbance, self.wheel_vel_limit, self.d, self.gain, self.radius = 0.0, 0.0, 0.0, 0.0, 0.0
        self.boundary = boundary_points
        self.stats = BarrierStats()
        self.quadprog_errors = quadprog_errors

    def _robust_rows(
        self, n: int, grads: list[FloatArray], robots: list[NDArray[np.intp]], h: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """Rows ``-sum_k g_k u_k <= gamma h^3 - disturbance sum_k |g_k D|_1`` over the ``2 n`` unknowns, for the
        gradients g_k (m, 2) with respect to the commands of the robots ``robots[k]`` (m,)."""
        a = np.zeros((h.size, 2 * n))
        rows = np.arange(h.size)
        worst = np.zeros(h.size)
        for g, robot in zip(grads, robots, strict=True):
            a[rows, 2 * robot] -= g[:, 0]
            a[rows, 2 * robot + 1] -= g[:, 1]
            worst += np.abs(g @ self.wheels_to_uni).sum(axis=1)
        return a, self.gain * h**3 - abs(self.disturbance) * worst  # the square of corners +/- disturbance

    def _gradient(self, diff: FloatArray, heading: FloatArray) -> FloatArray:
        """d|diff|^2 / du of a point d ahead of a robot with ``heading`` (m,), diff = its point minus another, (2, m):
        2 diff^T [cos, -d sin; sin, d cos], (m, 2)."""
        c, s = np.cos(heading), np.sin(heading)
        return 2 * np.column_stack([diff[0] * c + diff[1] * s, self.d * (diff[1] * c - diff[0] * s)])

    def _read_as_classic(self, dxu: Any, x: Any, obstacles: Any) -> tuple[FloatArray, FloatArray]:
        """The commands and poses, read in classic's order with classic's errors (a list, a 1-D array, poses of
        another number of robots than commands), and the numbers given, used as classic uses them at a call."""
        n = np.size(dxu[0, :])
        _ = obstacles.size
        headings = np.zeros(self.max_robots) if self.boundary is not None else np.zeros((1, self.max_robots))
        if n > 0 or not self.quadprog_errors:  # classic's robust barriers return at once for no robots
            headings[..., 0:n] = np.cos(x[2, :])  # classic's matrix for max_num_robots (an np.matrix without walls)
        _ = x[:2, :]
        disturbance, wheel_vel_limit, d, gain, radius = self.given
        if n >= 2:  # classic's pair rows use the radius, then the gain; its wheel rows the limit
            _ = radius**2, -gain
        _ = -wheel_vel_limit
        self.disturbance, self.wheel_vel_limit = float(disturbance), float(wheel_vel_limit)
        self.d, self.gain, self.radius = float(d), float(gain), float(radius)
        return np.asarray(dxu, dtype=float), np.asarray(x, dtype=float)

    def __call__(self, dxu: FloatArray, x: FloatArray, obstacles: FloatArray = np.empty(0)) -> FloatArray:  # noqa: B008
        dxu, x = self._read_as_classic(dxu, x, obstacles)
        n = dxu.shape[1]
        theta = x[2]
        points = x[:2] + self.d * np.vstack([np.cos(theta), np.sin(theta)])
        i, j = np.triu_indices(n, k=1)
        diff = points[:, i] - points[:, j]
        h = np.einsum('ij,ij->j', diff, diff) - self.radius**2
        blocks = [self._robust_rows(n, [self._gradient(diff, theta[i]), self._gradient(-diff, theta[j])], [i, j], h)]
        obstacles = np.asarray(obstacles, dtype=float)
        if obstacles.size:
            robot, point = np.divmod(np.arange(n * obstacles.shape[1]), obstacles.shape[1])
            away = points[:, robot] - obstacles[:, point]
            h = np.einsum('ij,ij->j', away, away) - self.radius**2
            blocks.append(self._robust_rows(n, [self._gradient(away, theta[robot])], [robot], h))
        if self.boundary is not None:
            blocks.append(self._wall_rows(points, theta, self.boundary))
        inverse = np.linalg.inv(self.wheels_to_uni)
        wheel_rows = np.kron(np.eye(n), np.vstack([inverse, -inverse]))  # +/- w = +/- D^-1 u <= limit
        blocks.append((wheel_rows, np.full(4 * n, self.wheel_vel_limit)))
        a = np.vstack([rows for rows, _ in blocks])
        b = np.concatenate([right for _, right in blocks])
        _ = np.dot(np.linalg.inv(self.wheels_to_uni), dxu)  # classic maps the commands to wheel speeds: its error
        scale = np.tile([1.0, self.d], n)  # unknowns z = (v, d omega): the objective becomes |z - z_hat|^2
        self.stats.solves += 1
        self.stats.rows_last = a.shape[0]
        if self.boundary is not None and qp_solver() == 'testbed':
            return self._classic_solve(dxu, a, b)
        if self.quadprog_errors and self.d == 0:
            raise ValueError('matrix G is not positive definite')
        z = least_distance((dxu * scale.reshape(n, 2).T).reshape(-1, order='F'), a / scale, b)
        if z is None and self.quadprog_errors:
            raise ValueError('constraints are inconsistent, no solution')
        if z is None:
            self.stats.failures += 1
            message = f'robust barrier QP infeasible at solve {self.stats.solves}; commanding zero velocities'
            self.stats.messages.append(message)
            warnings.warn(f'QP failed. Commanding zero velocities. ({message})', RuntimeWarning, stacklevel=2)
            return np.zeros_like(dxu)
        safe: FloatArray = z.reshape(2, n, order='F') / scale.reshape(n, 2).T
        return safe

    def _classic_solve(self, dxu: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray:
        """Classic's with-walls solve: cvxopt at its loose options on the wheel speeds w (u = D w), minimising
        |L (w - w_hat)|^2 with L = diag(1, d) D, the rows in classic's order (pairs and obstacles, each robot's four
        walls, the upper then the lower wheel bounds), and its answer taken whatever cvxopt's status, as classic."""
        n = dxu.shape[1]
        walls = a.shape[0] - 8 * n  # the walls' first row: after the pairs and obstacles, before the wheel bounds
        order = np.r_[np.arange(walls), walls + np.arange(4 * n).reshape(4, n).T.ravel()]
        to_wheels = np.kron(np.eye(n), self.wheels_to_uni)
        g = np.vstack([a[order] @ to_wheels, np.eye(2 * n), -np.eye(2 * n)])
        h = np.r_[b[order], np.full(4 * n, self.wheel_vel_limit)]
        metric = np.kron(np.eye(n), np.diag([1.0, self.d]) @ self.wheels_to_uni)
        w_hat = (np.linalg.inv(self.wheels_to_uni) @ dxu).reshape(-1, order='F')
        quadratic = 2 * metric.T @ metric
        solution = cvxopt.solvers.qp(
            cvxopt.matrix(quadratic),
            cvxopt.matrix(-(w_hat @ quadratic)),
            cvxopt.matrix(g),
            cvxopt.matrix(h),
            options=TESTBED_QP_OPTIONS,
        )
        wheels: FloatArray = self.wheels_to_uni @ np.array(solution['x']).reshape(2, n, order='F')
        return wheels

    def _wall_rows(self, points: FloatArray, theta: FloatArray, boundary: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``+/- pdot_y, +/- pdot_x <= 0.4 gamma (room - R/2)^3`` per robot, pdot = [cos, -d sin; sin, d cos] u."""
        xmin, xmax, ymin, ymax = boundary
        n, c, s = points.shape[1], np.cos(theta), np.sin(theta)
        robots = np.arange(n)
        a = np.zeros((4 * n, 2 * n))
        b = np.empty(4 * n)
        half, gain = self.radius / 2, 0.4 * self.gain
        for k, (sign, along, across, room) in enumerate(
            (
                (1.0, s, self.d * c, ymax - half - points[1]),
                (-1.0, s, self.d * c, points[1] - ymin - half),
                (1.0, c, -self.d * s, xmax - half - points[0]),
                (-1.0, c, -self.d * s, points[0] - xmin - half),
            )
        ):
            a[k * n + robots, 2 * robots] = sign * along
            a[k * n + robots, 2 * robots + 1] = sign * across
            b[k * n : (k + 1) * n] = gain * room**3
        return a, b


def create_robust_barriers(
    max_num_obstacles: int = 100,
    max_num_robots: int = 30,
    d: float = 5,
    wheel_vel_limit: float = 12.5,
    base_length: float = 0.105,
    wheel_radius: float = 0.016,
    projection_distance: float = 0.05,
    gamma: float = 150,
    safety_radius: float = 0.12,
) -> RobustCertificate:
    """Classic: the robust certificate without walls; ``d`` is the wheel disturbance, ``gamma`` the barrier gain."""
    return RobustCertificate(
        d,
        wheel_vel_limit,
        base_length,
        wheel_radius,
        projection_distance,
        gamma,
        safety_radius,
        None,
        sizes=(max_num_obstacles, max_num_robots, 4),
        quadprog_errors=True,
    )
