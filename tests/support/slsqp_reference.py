"""An independent reference for the planner: (p1)-(p7) as a smooth nonlinear program solved by scipy SLSQP.

Written without the planner's code: the unknowns are the speed v and the density rho at the nodes of a coarse
grid, interpolated like a Plan (linear in w = 1/v and in rho); every constraint is imposed over each interval in
its exact nonlinear form (no convex-concave linearisation), with curvature and width bounds recomputed here
from the tube. The benchmark ``benchmarks/plan_bench.py`` uses it as the reference it is compared against.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize

from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.params import PlanningOptions, SwarmParams

RHO_FLOOR = 1e-3  # (p5)'s strictly positive density, as the paper's rho > 0


def slsqp_plan(
    tube: VirtualTube, swarm: SwarmParams, options: PlanningOptions, n_intervals: int, *, v0: float, rho0: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Grid, speed, density and objective value of the SLSQP solution on ``n_intervals`` equal intervals."""
    l = np.linspace(0.0, tube.length_m, n_intervals + 1)
    dl = l[1] - l[0]
    n = l.size
    sub = np.linspace(l[:-1], l[1:], 41, axis=1)
    radius = np.array([np.min(tube.curvature_radius(row)) for row in sub])
    interval_cap = np.minimum(np.sqrt(swarm.a_n_mps2 * radius), swarm.v_max_mps)
    node_cap = np.minimum(np.append(interval_cap, np.inf), np.insert(interval_cap, 0, np.inf))
    ratio = np.array(
        [np.max(np.abs(tube.half_width(row) / tube.half_width(row + options.lookahead_m) - 1)) for row in sub]
    )
    a_rho, a_v, mu = swarm.a_rho, swarm.a_v_mps2, options.density_weight

    def split(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return 1.0 / x[:n], x[n:]

    def objective(x: np.ndarray) -> float:
        w, rho = split(x)
        e = rho - swarm.rho_d_per_m2
        density = np.sum(dl / 3 * (e[:-1] ** 2 + e[:-1] * e[1:] + e[1:] ** 2))
        return float(np.sum(dl / 2 * (w[:-1] + w[1:])) + mu * density)

    def inequalities(x: np.ndarray) -> np.ndarray:
        w, rho = split(x)
        dw, drho = np.diff(w), np.diff(rho)
        rows = []
        for wj in (w[:-1], w[1:]):
            rows += [a_v * dl * wj**3 - dw, a_v * dl * wj**3 + dw]  # (p3) |w'| <= a_v w^3
            rows += [a_rho * dl * wj - drho, a_rho * dl * wj + drho]  # (p6)
            for rho_i in (rho[:-1], rho[1:]):
                rows.append(a_rho * options.lookahead_m * wj - ratio * rho_i)  # (p7), local width
        return np.concatenate(rows)

    bounds = [(swarm.v_min_mps, cap) for cap in node_cap] + [(RHO_FLOOR, swarm.rho_max_per_m2)] * n
    x0 = np.concatenate([np.full(n, swarm.v_min_mps), np.full(n, rho0)])
    x0[0] = v0
    constraints = [
        {'type': 'ineq', 'fun': inequalities},
        {'type': 'eq', 'fun': lambda x: np.array([x[0] - v0, x[n] - rho0])},
    ]
    result = minimize(
        objective, x0, method='SLSQP', bounds=bounds, constraints=constraints, options={'maxiter': 500, 'ftol': 1e-10}
    )
    if not result.success:
        msg = f'SLSQP reference failed: {result.message}'
        raise RuntimeError(msg)
    return l, result.x[:n], result.x[n:], float(result.fun)
