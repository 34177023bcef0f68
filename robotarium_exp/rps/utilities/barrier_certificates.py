"""V2's barrier certificates on one vectorised QP core (the classic ones build on it too).

Every certificate solves ``min ||u - u_hat||^2`` subject to the pairwise barrier rows
``-2 (x_i - x_j)^T (u_i - u_j) <= gamma h_ij^3`` with ``h_ij = ||x_i - x_j||^2 - R^2``, optionally the boundary rows
``+/- u <= 0.4 gamma (distance to the wall - R/2)^3`` and (V2) the 8-sided speed polygon, built with numpy at once.
Two ways to solve it (`use_qp_solver`):

- ``'testbed'``, the default: cvxopt stopped at the testbed's tolerances (1e-2, at most 50 iterations) on every row,
  as the testbed's certificates do (the same rows in V2's order, `barrier_rows`: cvxopt's answer to an infeasible
  QP, two robots at one point, depends on the order). Its answers are not the optimum, and the difference matters:
  with the exact optimum the initializer's 90 % duration quantile was 15-25 % lower than V2's
  (``docs/robotarium.md`` §2.6). With the testbed's solver a script (and the initializer) runs as on the official
  simulators, step for step.
- ``'exact'``: DAQP, a dual active-set solver, on the same constraints folded (`bounded_barrier_rows`: the
  walls and the polygon's sides along the axes bound u's components, opposite diagonal sides make one two-sided row)
  and without the pair rows that cannot bind (with the speed polygon, none can once gamma h^3 >= 4 d u_max /
  cos(pi/8), ``docs/ecosystem.md`` §2): the exact optimum, about twenty times faster than the PyPI simulator's
  certificate at N = 20, and infeasibility reported instead of an approximate point. A certificate starts each
  solve from the rows active at its last answer (`warm_least_distance`): an answer so found is kept only if
  it meets the KKT conditions, else DAQP solves from scratch.

An infeasible or failed solve does what ``rps`` does (zero velocities, a warning) but is never silent: every
certificate counts its solves and failures in ``certificate.stats``.

V2's names and keyword defaults: ``create_si_barrier_certificate``, ``create_si_barrier_certificate_with_boundary``,
``create_uni_barrier_certificate``, ``create_uni_barrier_certificate_with_boundary`` (whose certificate also takes
V2's ``obstacles``), and its QP helper ``_solve_qp``. As V2: the speed polygon, not a pre-scaling, limits the speed;
a lone robot's command passes unchanged; the boundary certificates put all eight polygon sides at limit
cos(pi/8).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from functools import lru_cache
from typing import cast

import cvxopt
import daqp
import numpy as np
from numpy.typing import NDArray

from robotarium_exp.rps.errors import RobotariumError
from robotarium_exp.rps.robotarium_abc import ARENA
from robotarium_exp.rps.utilities.barrier_inputs import (
    V2_BOUNDARY,
    V2Arguments,
    checked_pair,
    one_row_rows,
    v2_positions,
)
from robotarium_exp.rps.utilities.barrier_rows import BarrierSpec, BoundedRows, barrier_rows, bounded_barrier_rows
from robotarium_exp.rps.utilities.transformations import create_si_to_uni_mapping, create_uni_to_si_mapping

FloatArray = NDArray[np.float64]


@dataclass
class BarrierStats:
    """Counters of one certificate: solves, infeasible or failed solves (zero velocities commanded), rows."""

    solves: int = 0
    failures: int = 0
    rows_last: int = 0
    messages: list[str] = field(default_factory=list)


DAQP_OPTIMAL = (1, 2)
"""DAQP exit flags of a solution (optimal, soft-optimal); negative flags are infeasible, cycling, limits."""

DAQP_ACTIVE = 1
"""DAQP's sense of a row in the starting working set (at its upper bound)."""

DAQP_LOWER = 2
"""DAQP's sense of a row at its lower bound (with `DAQP_ACTIVE`: in the starting working set there)."""

KKT_TOL = 1e-12
"""Largest violation of a unit row in an exact answer: DAQP's primal tolerance, and that of `kkt_point`."""

DAQP_OPTIONS = {'primal_tol': KKT_TOL}
"""DAQP's settings for the exact solves."""

_NONE = np.zeros(0, dtype=np.intp)
"""No rows: an empty seed, no active set."""
_NONE.flags.writeable = False

TESTBED_QP_OPTIONS = {'show_progress': False, 'reltol': 1e-2, 'feastol': 1e-2, 'maxiters': 50}
"""cvxopt's options in the testbed's certificates (V2 and classic alike)."""

QP_SOLVERS = ('testbed', 'exact')
_qp_solver = ['testbed']


def use_qp_solver(name: str) -> str:
    """Choose how every certificate solves its QP from now on; returns the previous choice.

    ``'testbed'`` (the default): cvxopt at the testbed's options on every row, as V2 and classic do, so a script's
    certificates answer what the testbed's (and the official simulators') answer, run for run; an answer is within
    about 1e-2 of the optimum. ``'exact'``: DAQP on the rows that can bind, the exact optimum, about twenty times
    faster than the PyPI simulator's certificate at N = 20.
    """
    if name not in QP_SOLVERS:
        msg = f'unknown QP solver {name!r}; choose one of {", ".join(QP_SOLVERS)}.'
        raise RobotariumError(msg)
    previous, _qp_solver[0] = _qp_solver[0], name
    return previous


def qp_solver() -> str:
    """The certificates' QP solver now: 'testbed' or 'exact' (`use_qp_solver`)."""
    return _qp_solver[0]


def least_distance(u_hat: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray | None:
    """argmin ||u - u_hat||^2 subject to a u <= b, exactly; None if the QP is infeasible or the solver fails."""
    if a.shape[0] == 0 or np.all(a @ u_hat <= b):
        unchanged: FloatArray = u_hat.copy()
        return unchanged
    rows = BoundedRows(a, np.full(b.size, -np.inf), b, np.arange(b.size))
    solved = _daqp(u_hat, rows, _NONE, _NONE)
    return None if solved is None else solved[0]


def warm_least_distance(
    u_hat: FloatArray, rows: BoundedRows, seed: NDArray[np.intp], sides: NDArray[np.intp]
) -> tuple[FloatArray, NDArray[np.intp], FloatArray] | None:
    """argmin ||u - u_hat||^2 subject to ``rows.lower <= C u <= rows.upper`` (`BoundedRows`), started from a
    guess of its active rows ``seed`` (indices into C) at their ``sides`` (+1 upper, -1 lower): the answer, the
    rows active at it and their multipliers (positive at the upper bound, negative at the lower); None if the QP is
    infeasible or the solver fails.

    u_hat if it is feasible; else DAQP warm started from the seed, its answer kept only if it meets the KKT
    conditions (`kkt_point`); else DAQP from scratch. A seed whose rows u_hat mostly does not violate (the
    active rows of unrelated states, not of the last step of a trajectory) is dropped: DAQP takes more iterations
    from it than from scratch.
    """
    c_hat = rows.apply(u_hat)
    side = (c_hat > rows.upper).view(np.int8) - (c_hat < rows.lower).view(np.int8)  # the side u_hat violates
    if not side.any():
        return u_hat.copy(), _NONE, np.zeros(0)
    if seed.size > 0 and 4 * np.count_nonzero(side[seed] != sides) <= seed.size:
        warm = _daqp(u_hat, rows, seed, sides)
        if warm is not None and kkt_point(u_hat, rows, warm[1], warm[2]) is not None:
            return warm
    return _daqp(u_hat, rows, _NONE, _NONE)


def kkt_point(u_hat: FloatArray, rows: BoundedRows, active: NDArray[np.intp], lam: FloatArray) -> FloatArray | None:
    """u = u_hat - C[active]^T lam if it solves min ||u - u_hat||^2 subject to rows.lower <= C u <= rows.upper,
    else None.

    u is stationary by construction; it is the optimum if it meets the other KKT conditions: every row holds, and
    each row with a multiplier sits at the bound its sign names (upper if positive, lower if negative), to
    `KKT_TOL` times the row's norm; a negative multiplier on a row without lower bound never does.
    """
    general = active >= rows.bounded
    u = u_hat - rows.a[active[general] - rows.bounded].T @ lam[general]
    u[active[~general]] -= lam[~general]
    value = rows.apply(u)
    if np.max(np.maximum(value - rows.upper, rows.lower - value) / rows.norms) > KKT_TOL:
        return None
    at = np.where(
        lam > 0.0, rows.upper[active] - value[active], np.where(lam < 0.0, value[active] - rows.lower[active], 0)
    )
    if np.any(at > KKT_TOL * rows.norms[active]):
        return None
    optimum: FloatArray = u
    return optimum


def _daqp(
    u_hat: FloatArray, rows: BoundedRows, start: NDArray[np.intp], sides: NDArray[np.intp]
) -> tuple[FloatArray, NDArray[np.intp], FloatArray] | None:
    """DAQP on min ||u - u_hat||^2 subject to rows.lower <= C u <= rows.upper from the working set ``start`` (at
    ``sides``): u, the rows with a non-zero multiplier and their multipliers; None unless DAQP reports optimal.

    DAQP scales the rows to unit norm itself (its primal tolerance is per unit row) and answers the multipliers of
    the rows as given.
    """
    sense = np.zeros(rows.lower.size, dtype=np.int32)
    if start.size > 0:
        sense[start] = np.where(sides > 0, DAQP_ACTIVE, DAQP_ACTIVE | DAQP_LOWER)
    u, _, flag, info = daqp.solve(_identity(u_hat.size), -u_hat, rows.a, rows.upper, rows.lower, sense, **DAQP_OPTIONS)
    if flag not in DAQP_OPTIMAL:
        return None
    active = info['lam'].nonzero()[0]
    return u, active, info['lam'][active]


@lru_cache(maxsize=8)
def _identity(n: int) -> FloatArray:
    """The QP's Hessian for DAQP (writable, as DAQP's interface asks; DAQP only reads it)."""
    return np.eye(n)


def testbed_least_distance(u_hat: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray | None:
    """The testbed's answer to the same QP: cvxopt at `TESTBED_QP_OPTIONS`, None unless it reports optimal.

    Like the testbed, the solver always runs (a feasible command comes back moved by up to the tolerance).
    """
    n = u_hat.size
    try:
        solution = cvxopt.solvers.qp(
            cvxopt.spmatrix(2.0, range(n), range(n)),
            cvxopt.matrix(-2.0 * u_hat),
            cvxopt.matrix(np.ascontiguousarray(a, dtype=float)),
            cvxopt.matrix(np.asarray(b, dtype=float)),
            options=TESTBED_QP_OPTIONS,
        )
    except (ArithmeticError, ValueError):  # a singular KKT system: the testbed catches it and commands zeros
        return None
    if solution['status'] != 'optimal':
        return None
    return np.array(solution['x'], dtype=float).ravel()


def _solve_qp(N: int, vhat: FloatArray, A: FloatArray, b: FloatArray) -> FloatArray | None:
    """V2's QP helper: argmin ||v - vhat||^2 subject to A v <= b, v stacked robot by robot; (2, N) or None."""
    solve = testbed_least_distance if qp_solver() == 'testbed' else least_distance
    u = solve(
        np.asarray(vhat, dtype=float).reshape(-1, order='F'),
        np.asarray(A, dtype=float),
        np.asarray(b, dtype=float).ravel(),
    )
    return None if u is None else u.reshape(2, N, order='F')


class Certificate:
    """A barrier certificate: ``certificate(dxi, x) -> dxi`` for single integrators, with ``stats``.

    Given `V2Arguments` (V2's certificates), it reads its arguments and inputs as V2 does (`barrier_inputs`): no
    check up front, V2's error where V2 fails, V2's answer where V2 answers; given a `BarrierSpec` (classic's, whose
    checks come first), it refuses what is not two arrays of N columns.
    """

    def __init__(self, spec: BarrierSpec | V2Arguments) -> None:
        self._spec: BarrierSpec | None = spec if isinstance(spec, BarrierSpec) else None
        self.arguments: V2Arguments | None = None if isinstance(spec, BarrierSpec) else spec
        self.stats = BarrierStats()
        self._active_keys = _NONE
        """The keys (`BoundedRows`, ascending) of the rows active at the last exact answer."""
        self._active_sides = _NONE
        """Their sides: +1 at the upper bound, -1 at the lower."""
        self._active_n = 0

    def _warm_solve(self, u_hat: FloatArray, rows: BoundedRows) -> FloatArray | None:
        """The exact answer (2, N), started from the rows active at the last one; None if infeasible."""
        n, last = u_hat.size // 2, self._active_keys
        seed, sides = _NONE, _NONE
        if n == self._active_n and last.size > 0:  # keys ascend, so do the last active ones
            place = np.minimum(np.searchsorted(last, rows.keys), last.size - 1)
            seed = np.flatnonzero(last[place] == rows.keys)
            sides = self._active_sides[place[seed]]
        solved = warm_least_distance(u_hat, rows, seed, sides)
        self._active_n = n
        self._active_keys = _NONE if solved is None else rows.keys[solved[1]]
        self._active_sides = _NONE if solved is None else np.where(solved[2] > 0.0, 1, -1)
        return None if solved is None else solved[0].reshape(2, n)

    @property
    def spec(self) -> BarrierSpec:
        """The QP's numbers (V2's arguments are reached as V2 reaches them, with V2's errors)."""
        if self._spec is None:
            self._spec = cast(V2Arguments, self.arguments).spec()
        return self._spec

    def __call__(self, dxi: FloatArray, x: FloatArray) -> FloatArray:
        if self.arguments is not None:  # V2: a lone robot's command passes unchanged; the polygon limits the speed
            n = dxi.shape[1]
            if n < 2:
                unchanged: FloatArray = np.copy(dxi)
                return unchanged
            x = v2_positions(x, n, self.arguments.boundary_points is not None)
            spec = self.spec
            self.stats.solves += 1
            if dxi.shape[0] != 2 or not (np.isfinite(dxi).all() and np.isfinite(x).all()):
                return self._failed(n)  # V2's QP fails on such a command (or on NaN) and V2 commands zeros
            dxi = np.asarray(dxi, dtype=float)
        else:  # classic: no polygon, so the command is first scaled to the limit; a lone robot still meets walls
            dxi, x = checked_pair(dxi, x, 'dxi', 'x')
            n, spec = dxi.shape[1], self.spec
            if n < 2 and spec.boundary is None:
                lone: FloatArray = dxi.copy()
                return lone
            norms = np.hypot(dxi[0], dxi[1])
            over = norms > spec.magnitude_limit
            dxi = dxi.copy()
            dxi[:, over] *= spec.magnitude_limit / norms[over]
            self.stats.solves += 1
        if qp_solver() == 'exact' and x.shape[0] > 1:
            rows = bounded_barrier_rows(x[:2], spec)
            u = self._warm_solve(dxi.ravel(), rows)
            self.stats.rows_last = rows.lower.size
        else:  # V2 given one row of positions reads it as both coordinates (`one_row_rows`)
            a, b = barrier_rows(x[:2], spec) if x.shape[0] > 1 else one_row_rows(x, spec)
            u = _solve_qp(n, dxi, a, b)
            self.stats.rows_last = a.shape[0]
        return self._failed(n) if u is None else u

    def _failed(self, n: int) -> FloatArray:
        """What V2 commands when its QP fails (zero velocities), with a warning, counted in ``stats``."""
        self.stats.failures += 1
        message = f'barrier QP infeasible at solve {self.stats.solves}; commanding zero velocities'
        self.stats.messages.append(message)
        warnings.warn(f'QP failed. Commanding zero velocities. ({message})', RuntimeWarning, stacklevel=3)
        return np.zeros((2, n))


class UnicycleCertificate:
    """V2's certificate at projection points: ``certificate(dxu, poses) -> dxu``, with ``stats``.

    As V2: a lone robot's command passes unchanged; the poses and commands go through V2's maps (their checks and
    messages: `robotarium_exp.rps.utilities.transformations`), then the single-integrator certificate, then back.
    """

    def __init__(self, inner: Certificate, projection_distance: float) -> None:
        self.si_to_uni_dyn, self.uni_to_si_states = create_si_to_uni_mapping(projection_distance)
        self.uni_to_si_dyn, _ = create_uni_to_si_mapping(projection_distance)
        self.inner = inner
        self.d = projection_distance

    @property
    def stats(self) -> BarrierStats:
        return self.inner.stats

    def __call__(self, dxu: FloatArray, x: FloatArray, obstacles: FloatArray | None = None) -> FloatArray:
        """Safe commands; ``obstacles`` (2 x M points) join the QP as V2 has them: agents with zero nominal speed."""
        n = dxu.shape[1]
        if n < 2:
            unchanged: FloatArray = np.copy(dxu)
            return unchanged
        if isinstance(x, np.ndarray) and not (np.isfinite(dxu).all() and np.isfinite(x).all()):
            self.uni_to_si_states(np.nan_to_num(x))  # V2's maps check the shapes; then V2's QP fails on NaN
            self.uni_to_si_dyn(np.nan_to_num(dxu), np.nan_to_num(x))
            self.inner.stats.solves += 1
            return self.inner._failed(n)
        points, dxi = self.uni_to_si_states(x), self.uni_to_si_dyn(dxu, x)
        if obstacles is not None and obstacles.size > 0:
            points = np.hstack((points, obstacles))
            dxi = np.hstack((dxi, np.zeros((2, obstacles.shape[1]))))
        safe = self.inner(dxi, points)
        return self.si_to_uni_dyn(safe[:, :n], x)


# ---------------------------------------------------------------------- V2 names and defaults


def create_si_barrier_certificate(
    safety_radius: float = 0.15, barrier_gain: float = 100.0, magnitude_limit: float = 0.2
) -> Certificate:
    """V2: pairwise barriers and the speed polygon (the arguments are used as V2 uses them: `V2Arguments`)."""
    return Certificate(V2Arguments(safety_radius, barrier_gain, magnitude_limit))


def create_si_barrier_certificate_with_boundary(
    safety_radius: float = 0.15,
    barrier_gain: float = 100.0,
    magnitude_limit: float = 0.2,
    boundary_points: object = None,
) -> Certificate:
    """V2: pairwise and boundary barriers (default boundary [-1.7, 1.7, -1.1, 1.1], as V2) and the speed polygon,
    all eight sides at limit cos(pi/8)."""
    boundary = V2_BOUNDARY if boundary_points is None else boundary_points
    return Certificate(V2Arguments(safety_radius, barrier_gain, magnitude_limit, boundary))


def create_uni_barrier_certificate(
    barrier_gain: float = 100.0,
    safety_radius: float = 0.15,
    projection_distance: float = 0.05,
    velocity_magnitude_limit: float = 0.2,
) -> UnicycleCertificate:
    """V2: the SI certificate at projection points, radius safety_radius + 2 d."""
    create_si_to_uni_mapping(projection_distance)  # V2 creates its maps first: their check of the distance
    inner = V2Arguments(safety_radius + 2 * projection_distance, barrier_gain, velocity_magnitude_limit)
    return UnicycleCertificate(Certificate(inner), projection_distance)


def create_uni_barrier_certificate_with_boundary(
    safety_radius: float = 0.12,
    barrier_gain: float = 150.0,
    projection_distance: float = 0.03,
    velocity_magnitude_limit: float = 0.2,
    boundary_points: object = None,
) -> UnicycleCertificate:
    """V2: as above with the arena's boundary (V2's default) and the speed polygon's sides all at limit cos(pi/8).

    The certificate takes V2's third argument, ``obstacles`` (2 x M points to keep clear of).
    """
    create_si_to_uni_mapping(projection_distance)  # V2 creates its maps first: their check of the distance
    boundary = ARENA if boundary_points is None else boundary_points
    radius = safety_radius + 2 * projection_distance
    inner = V2Arguments(radius, barrier_gain, velocity_magnitude_limit, boundary)
    return UnicycleCertificate(Certificate(inner), projection_distance)
