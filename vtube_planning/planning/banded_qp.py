"""The planner's convex subproblem solved by a primal-dual interior-point method on banded normal equations.

The QP of `ConvexPlanner` for the linear predictive models
(``'local_width'`` and ``'none'``), written out as arrays.

Every constraint couples the unknowns of one grid interval at most, so with the unknowns interleaved as
x = (w_0, rho_0, w_1, rho_1, ..., w_K, rho_K) each row touches four consecutive entries, x[2k : 2k + 4], and the
normal matrix P + G' W G of an interior-point step is banded with three sub-diagonals, factorised by LAPACK's
banded Cholesky (``dpbtrf``). Rows are stored per interval as a (K, rows, 4) array of their four coefficients (the
bounds of grid point k + 1 sit in interval k), so that G is a CSR matrix of four entries per row and the normal
matrix is assembled from (K, 4, 4) blocks, weighted sums of products of row entries.

The method is Mehrotra's predictor-corrector (Nocedal and Wright 2006, §16.6) from an infeasible start: the first
subproblem starts at the tangent point, each later one at the last solution (a warm start). w_0 and rho_0, fixed
by the initial values, are held at their values. Dot products avoid BLAS, whose threads stall when another process
holds the other core. Every inequality is imposed with a relative margin ``MARGIN``, so that the solution, which
meets a constraint only to the solver's tolerance, satisfies the original constraint.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.linalg.lapack import dpbtrf as _band_factor
from scipy.linalg.lapack import dpbtrs as _band_solve

from vtube_planning.errors import SolverError
from vtube_planning.planning.braking import braking_tangent
from vtube_planning.planning.constraints import RHO_EPSILON
from vtube_planning.planning.last_out import QuadraticModel
from vtube_planning.planning.problem import Problem

FloatArray = NDArray[np.float64]

MARGIN = 1e-9
"""Relative tightening of every inequality, so that the solver's tolerance does not show in the certificate."""
TOLERANCE = 1e-11
"""Stop when the scaled primal and dual residuals and the mean complementarity are below this."""
STALLED_TOLERANCE = 1e-9
"""The residuals and gap accepted when the iteration stalls above TOLERANCE (see ``BandedPlanner._solve``)."""
MAX_STEPS = 100
"""Interior-point iterations before giving up (a well-posed subproblem takes 15 to 30)."""
STEP_FRACTION = 0.995
"""Fraction of the step to the boundary of the positive orthant taken at each iteration."""

WARM_FLOOR = (1e-6, 1e-2)
"""Bounds of the floor put under the warm start's slacks and multipliers (tuned on scenes A-D and Robotarium)."""

# local slots of an interval's four unknowns, and the slot pairs of the lower triangle of a (4, 4) block
W_LEFT, RHO_LEFT, W_RIGHT, RHO_RIGHT = range(4)
SLOT_PAIRS = np.array([(i, j) for i in range(4) for j in range(i + 1)])


class BandedPlanner:
    """The QP of one convex-concave iteration (same interface as the cvxpy ``ConvexPlanner``)."""

    def __init__(self, problem: Problem) -> None:
        self.problem = problem
        n = problem.l_m.size
        k = n - 1
        self.n, self.k = n, k
        dl = np.diff(problem.l_m)
        self.dl = dl
        self._p3 = slice(0, 4)  # (p3)'s four rows per interval come first; set_tangent fills them
        self._braking = slice(4, 8) if problem.options.braking_room else None  # then the room for braking's
        self.g, self.h, self.kept = _constraint_rows(problem, dl)  # (K, kinds, 4), (K, kinds), (K, kinds)
        self.interval = np.nonzero(self.kept)[0]  # (m,) each imposed row's interval, ascending
        self.first_row = np.searchsorted(self.interval, np.arange(k))  # (K,) where each interval's rows start
        self.fixed = np.array([1.0 / problem.v0_mps, problem.rho0_per_m2])
        self.p_diag, self.p_off, self.q, self.constant = _objective(problem, dl)
        self._base = (self.p_diag, self.q, self.constant)  # (p1) without the exit model
        self._end_curvature: tuple[float, float] | None = None  # the exit model's, on w_K and rho_K
        self.value = float('nan')
        self.steps = 0  # interior-point iterations of the last solve
        self._change = 1.0  # relative change of the objective at the last solve
        self._last: tuple[FloatArray, FloatArray] | None = None  # the last solution and its multipliers
        self._tangent = (problem.w_start, problem.rho_start)

    def set_tangent(self, w_bar: FloatArray, rho_bar: FloatArray) -> None:
        """Linearise (p3) at ``w_bar`` (normalised form dw / (a_v dl wbar^3) <= 3 w / wbar - 2, then rows scaled)."""
        self._tangent = (w_bar, rho_bar)
        a_v = self.problem.swarm.a_v_mps2 * (1.0 - MARGIN)
        block = self.g[:, self._p3, :]
        block[:] = 0.0
        row = 0
        for sign in (1.0, -1.0):
            for end, w_end in ((W_LEFT, w_bar[:-1]), (W_RIGHT, w_bar[1:])):
                inv_scale = sign / (a_v * self.dl * w_end**3)
                block[:, row, W_RIGHT] += inv_scale
                block[:, row, W_LEFT] -= inv_scale
                block[:, row, end] -= 3.0 / w_end
                row += 1
        if self._braking is not None:
            self._set_braking(self._braking, rho_bar)

    def _set_braking(self, rows: slice, rho_bar: FloatArray) -> None:
        """Linearise the room for braking, constraint ``rows``, at ``rho_bar``: w_i >= slope_j rho_j + intercept_j for
        both ends i, j of every interval, with h's tangent at rho_bar_j (`braking.braking_tangent`)."""
        slope, intercept = braking_tangent(self.problem.swarm, rho_bar)
        block = self.g[:, rows, :]
        block[:] = 0.0
        row = rows.start
        for w_end in (W_LEFT, W_RIGHT):
            for rho_end, j in ((RHO_LEFT, slice(None, -1)), (RHO_RIGHT, slice(1, None))):
                block[:, row - rows.start, w_end] = -(1.0 - MARGIN)
                block[:, row - rows.start, rho_end] = slope[j]
                self.h[:, row] = -intercept[j]
                row += 1

    def set_exit_model(self, model: QuadraticModel) -> None:
        """Add the convex model of the last-robot-out exit term (`last_out.ExitTerm.model`) to (p1), in place of the
        previous one."""
        p_diag, q, constant = self._base
        (lw, lr), (a, b) = model.linear, model.curvature
        self.p_diag = p_diag.copy()
        self.p_diag[-1] += b
        self.q = q.copy()
        self.q[-2:] += (lw, lr)
        self.constant = constant + model.constant
        self._end_curvature = (a, b)

    def solve(self) -> tuple[FloatArray, FloatArray]:
        """Solve the current subproblem (rows scaled to unit largest coefficient); (p1) is left in `value`."""
        g, h = self.g[self.kept], self.h[self.kept]
        scale = np.abs(g).max(axis=1)
        x = self._solve(g / scale[:, None], h / scale)
        w, rho = x[0::2].copy(), x[1::2].copy()
        value = float(self.q @ x + 0.5 * x[1::2] @ self._p_times(x)[1::2]) + self.constant
        if self._end_curvature is not None:
            value += 0.5 * self._end_curvature[0] * x[-2] ** 2
        self._change = abs(self.value - value) / abs(value) if np.isfinite(self.value) else 1.0
        self.value = value
        return w, rho

    def _p_times(self, x: FloatArray) -> FloatArray:
        out = np.zeros_like(x)
        rho = x[1::2]
        out[1::2] = self.p_diag * rho
        out[1:-2:2] += self.p_off * rho[1:]
        out[3::2] += self.p_off * rho[:-1]
        if self._end_curvature is not None:
            out[-2] += self._end_curvature[0] * x[-2]
        return out

    def _solve(self, g: FloatArray, h: FloatArray) -> FloatArray:
        """Mehrotra's method on rows ``g`` (m, 4) (the coefficients of x[2k : 2k + 4], k each row's interval)."""
        n2, m = 2 * self.n, h.size
        columns = 2 * self.interval[:, None] + np.arange(4)
        big_g = sp.csr_matrix((g.ravel(), columns.ravel(), np.arange(0, 4 * m + 1, 4)), shape=(m, n2))
        big_gt = big_g.T.tocsr()
        products = g[:, SLOT_PAIRS[:, 0]] * g[:, SLOT_PAIRS[:, 1]]  # (m, 10)
        x, s, z = self._start(big_g, h)
        h_norm = 1.0 + np.abs(h).max()
        q_norm = 1.0 + np.abs(self.q).max()
        stalled: tuple[float, FloatArray, FloatArray] | None = None  # the best iterate within STALLED_TOLERANCE
        for step in range(1, MAX_STEPS + 1):
            r_dual = self._p_times(x) + self.q + big_gt @ z
            r_dual[:2] = 0.0
            r_primal = big_g @ x + s - h
            gap = float(np.sum(s * z)) / m  # not BLAS ddot, which threads above 10,000 entries
            primal, dual = np.abs(r_primal).max(), np.abs(r_dual).max()
            self.steps = step
            if primal <= TOLERANCE * h_norm and dual <= TOLERANCE * q_norm and gap <= TOLERANCE:
                self._last = (x.copy(), z.copy())
                return x
            worst = max(primal / h_norm, dual / q_norm, gap)
            if worst <= STALLED_TOLERANCE and (stalled is None or worst < stalled[0]):
                stalled = (worst, x.copy(), z.copy())
            try:
                factor = self._factor(products, z / s)
            except SolverError:
                if stalled is None:
                    raise
                break
            alpha, dx, ds, dz = _mehrotra_step(big_g, big_gt, factor, s, z, (r_primal, r_dual), gap)
            x += alpha * dx
            s += alpha * ds
            z += alpha * dz
        if stalled is not None:
            # the weights z / s span 30 orders of magnitude near the end, and where the optimum is not a vertex in w
            # rounding takes the normal matrix's definiteness: the best iterate within STALLED_TOLERANCE is the answer
            self._last = (stalled[1], stalled[2])
            best: FloatArray = stalled[1].copy()
            return best
        msg = (
            f'the banded interior-point solver did not converge in {MAX_STEPS} iterations on a planning subproblem '
            "shown feasible beforehand; plan with formulation='cvxpy' and report this scene."
        )
        raise SolverError(msg)

    def _start(self, big_g: sp.csr_matrix, h: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """The first iterate (x, s, z): at the tangent point (feasible) with slacks and multipliers at least the
        largest floor, or warm, the last solution with its slacks and multipliers kept off zero by about as much as
        the objective moved at the last convex-concave iteration (the tangent moves about that much)."""
        if self._last is None:
            x, z, floor = np.empty(2 * self.n), np.full_like(h, WARM_FLOOR[1]), WARM_FLOOR[1]
            x[0::2], x[1::2] = self._tangent
        else:
            floor = min(WARM_FLOOR[1], max(WARM_FLOOR[0], self._change))
            x, z = self._last[0].copy(), np.maximum(self._last[1], floor)
        x[:2] = self.fixed
        s = np.maximum(h - big_g @ x, floor)
        return x, s, z

    def _factor(self, products: FloatArray, weight: FloatArray) -> FloatArray:
        """Lower banded Cholesky factor of P + G' W G, with the fixed w_0, rho_0 rows replaced by identity rows.

        ``products`` holds g_ri g_rj for the ten slot pairs (i, j), i >= j, of every row: (m, 10).
        """
        n2, k = 2 * self.n, self.k
        blocks = np.add.reduceat(products * weight[:, None], self.first_row, axis=0)  # (K, 10) lower triangles
        band = np.zeros((4, n2))
        for (i, j), block in zip(SLOT_PAIRS, blocks.T, strict=True):
            band[i - j, j : j + 2 * k : 2] += block
        band[0, 1::2] += self.p_diag
        band[2, 1:-2:2] += self.p_off
        if self._end_curvature is not None:
            band[0, -2] += self._end_curvature[0]
        band[:, :2] = 0.0
        band[0, :2] = 1.0
        factor: FloatArray
        factor, info = _band_factor(band, lower=1, overwrite_ab=1)
        if info != 0:
            msg = f'the normal matrix of a planning subproblem is not positive definite (LAPACK dpbtrf info {info})'
            raise SolverError(msg)
        return factor


def _constraint_rows(problem: Problem, dl: FloatArray) -> tuple[FloatArray, FloatArray, NDArray[np.bool_]]:
    """Every kind of row of every interval, each inequality tightened by ``MARGIN``: coefficients (K, kinds, 4) of
    the interval's unknowns, right-hand sides (K, kinds), and which rows are imposed (K, kinds). (p3)'s four kinds
    come first, zero until `BandedPlanner.set_tangent`."""
    swarm, options = problem.swarm, problem.options
    k = dl.size
    tight = 1.0 - MARGIN
    rows: list[FloatArray] = []  # (K, 4) coefficients per row kind
    rhs: list[FloatArray] = []  # (K,) right-hand sides
    needed: list[NDArray[np.bool_]] = []  # (K,) the intervals whose row of this kind can bind

    def add(coefficients: dict[int, FloatArray | float], b: FloatArray | float, where: object = True) -> None:
        block = np.zeros((k, 4))
        for slot, value in coefficients.items():
            block[:, slot] = value
        rows.append(block)
        rhs.append(np.broadcast_to(np.asarray(b, dtype=float), (k,)).copy())
        needed.append(np.broadcast_to(np.asarray(where, dtype=bool), (k,)))

    for _ in range(4):  # (p3), linearised at the previous iterate
        add({}, -2.0)
    for _ in range(4 if options.braking_room else 0):  # the room for braking, linearised at the previous iterate
        add({}, 0.0)
    # (p6): +-(rho_{k+1} - rho_k) - a_rho dl_k w_j <= 0 for j = k, k+1
    rate = swarm.a_rho * dl * tight
    for sign in (1.0, -1.0):
        for end in (W_LEFT, W_RIGHT):
            add({RHO_RIGHT: sign, RHO_LEFT: -sign, end: -rate}, 0.0)
    if options.predictive_model == 'local_width':
        # (p7), local width: ratio_k rho_i - a_rho dl_p w_j <= 0 for i, j in {k, k+1}; left out where the width
        # does not change over the look-ahead (ratio 0: the row says w >= 0, which the bounds imply)
        budget = swarm.a_rho * options.lookahead_m * tight
        for density in (RHO_LEFT, RHO_RIGHT):
            for end in (W_LEFT, W_RIGHT):
                add({density: problem.width_ratio, end: -budget}, 0.0, problem.width_ratio > 0.0)
    elif options.predictive_model != 'none':
        msg = f'the banded solver takes linear predictive models only, not {options.predictive_model!r}'
        raise ValueError(msg)
    # bounds of grid points 1..K (w_0 and rho_0 are fixed), grid point k + 1 in interval k's right slots:
    # w in [(1 + margin) / cap, tight / v_min], rho in [(1 + margin) eps, tight rho_max]
    low_w, high_w = (1.0 + MARGIN) / problem.speed_cap_mps[1:], tight / swarm.v_min_mps
    add({W_RIGHT: -1.0}, -low_w)
    add({W_RIGHT: 1.0}, high_w)
    add({RHO_RIGHT: -1.0}, -RHO_EPSILON * (1.0 + MARGIN))
    add({RHO_RIGHT: 1.0}, tight * swarm.rho_max_per_m2)
    return np.ascontiguousarray(np.stack(rows, axis=1)), np.stack(rhs, axis=1), np.stack(needed, axis=1)


def _objective(problem: Problem, dl: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, float]:
    """(p1) as 0.5 x' P x + q' x + constant: P's diagonal on rho and its entries between rho_k and rho_{k+1}, q,
    the constant. The time term is the trapezoid (exact for w linear), the density term mu times the exact
    integral of (rho - rho_d)^2 for rho linear, mu sum dl_k (e_k^2 + e_k e_{k+1} + e_{k+1}^2) / 3."""
    node_dl = np.concatenate([dl, [0.0]]) + np.concatenate([[0.0], dl])
    mu = problem.options.density_weight
    p_diag = mu * 2.0 * node_dl / 3.0  # on rho
    p_off = mu * dl / 3.0  # between rho_k and rho_{k+1}
    rho_d = problem.swarm.rho_d_per_m2
    q = np.zeros(2 * problem.l_m.size)
    q[0::2] = 0.5 * node_dl
    q[1::2] = -rho_d * (p_diag + np.concatenate([p_off, [0.0]]) + np.concatenate([[0.0], p_off]))
    constant = 0.5 * rho_d**2 * (p_diag.sum() + 2.0 * p_off.sum())
    return p_diag, p_off, q, constant


def _mehrotra_step(
    big_g: sp.csr_matrix,
    big_gt: sp.csr_matrix,
    factor: FloatArray,
    s: FloatArray,
    z: FloatArray,
    residuals: tuple[FloatArray, FloatArray],
    gap: float,
) -> tuple[float, FloatArray, FloatArray, FloatArray]:
    """Mehrotra's predictor-corrector step: the step length and the direction (dx, ds, dz)."""
    m = s.size
    dx, ds, dz = _direction(big_g, big_gt, factor, s, z, residuals, s * z)
    alpha = _largest_step(s, ds, z, dz)
    gap_affine = float(np.sum((s + alpha * ds) * (z + alpha * dz))) / m
    sigma = (gap_affine / gap) ** 3
    dx, ds, dz = _direction(big_g, big_gt, factor, s, z, residuals, s * z + ds * dz - sigma * gap)
    alpha = min(1.0, STEP_FRACTION * _largest_step(s, ds, z, dz))
    return alpha, dx, ds, dz


def _direction(
    big_g: sp.csr_matrix,
    big_gt: sp.csr_matrix,
    factor: FloatArray,
    s: FloatArray,
    z: FloatArray,
    residuals: tuple[FloatArray, FloatArray],
    r_comp: FloatArray,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The Newton step (dx, ds, dz) for complementarity residual ``r_comp``, slacks eliminated (normal equations)."""
    r_primal, r_dual = residuals
    rhs = -r_dual - big_gt @ ((z * r_primal - r_comp) / s)
    rhs[:2] = 0.0  # w_0 and rho_0 stay
    dx, _ = _band_solve(factor, rhs, lower=1)
    ds = -r_primal - big_g @ dx
    dz = (-r_comp - z * ds) / s
    return dx, ds, dz


def _largest_step(s: FloatArray, ds: FloatArray, z: FloatArray, dz: FloatArray) -> float:
    """The largest alpha in (0, 1] keeping s + alpha ds >= 0 and z + alpha dz >= 0 (s, z > 0)."""
    shrink = max(float(np.max(-ds / s)), float(np.max(-dz / z)))
    return 1.0 if shrink <= 1.0 else 1.0 / shrink
