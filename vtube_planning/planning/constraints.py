"""The planning problem's bounds, and its objective (p1) and constraints (p2)-(p7) evaluated on a sampled plan.

A plan is used with its slowness w = 1/v and its density linear between grid points; `certify` evaluates
every constraint on that interpolated plan on a grid ten times finer than the solve grid.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.params import PlanningOptions, SwarmParams
from vtube_planning.planning.braking import braking_excess
from vtube_planning.planning.density import predicted_density
from vtube_planning.planning.last_out import last_out_terms

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

RHO_EPSILON = 1e-3
"""Lower bound of the density in (p5), robots/m^2: the paper's strict ``rho > 0`` (resolution A14)."""
FINE_FACTOR = 10
"""The certificate's grid is this many times finer than the solve grid."""
ACTIVE_RTOL = 1e-3
"""A constraint is reported active at a grid point when its relative slack is below this."""
CONSTRAINTS = ('p2', 'p3', 'p4', 'p5', 'p6', 'p7', 'initial')
"""The certificate's entries (and ``'braking'`` for a plan with ``braking_room``)."""
MEANINGS = {
    'p2': 'the speed band [v_min, v_max]',
    'p3': 'the speed change a_v',
    'p4': 'the curvature speed limit sqrt(a_n r_t)',
    'p5': 'the density bounds (0, rho_max]',
    'p6': 'the density change a_rho',
    'p7': 'the predicted density change a_rho over the look-ahead',
    'initial': 'the initial speed and density',
    'braking': 'the spacing for braking to v_min (planning option braking_room)',
}
"""What each certificate entry bounds, for messages."""


RELAXED_MPS2 = 1e6
"""a_v and a_n as a relaxed plan sees them (``options.freedom = 'relaxed'``), m/s^2: (p3) and (p4) never bind (a
speed change from v_max to v_min within a grid step of 1e-4 m at 5 m/s needs 1.3e5)."""


def planned_limits(swarm: SwarmParams, options: PlanningOptions) -> SwarmParams:
    """The swarm as the planner holds it: itself, or with ``options.freedom = 'relaxed'`` a_v and a_n raised to
    `RELAXED_MPS2`, so that (p3) and (p4) are left out (``docs/theory.md`` §8.8)."""
    if options.freedom == 'paper':
        return swarm
    return replace(swarm, a_v_mps2=RELAXED_MPS2, a_n_mps2=RELAXED_MPS2)


def initial_conditions(swarm: SwarmParams, options: PlanningOptions) -> tuple[float, float]:
    """Boundary values (v_a(0), rho_a(0)): the options', or v_min (v_max for a relaxed plan) and the packing density
    (resolution A15)."""
    start = swarm.v_min_mps if options.freedom == 'paper' else swarm.v_max_mps
    v0 = start if options.v0_mps is None else float(options.v0_mps)
    rho0 = swarm.rho_packing if options.rho0_per_m2 is None else float(options.rho0_per_m2)
    return v0, rho0


def curvature_speed_limit(tube: VirtualTube, swarm: SwarmParams, l_m: FloatArray) -> FloatArray:
    """sqrt(a_n r_t(l)) of (p4), inf where the tube is straight."""
    return np.sqrt(swarm.a_n_mps2 * np.asarray(tube.curvature_radius(l_m)))


def objective_terms(
    l_m: FloatArray,
    speed_mps: FloatArray,
    density: FloatArray,
    swarm: SwarmParams,
    options: PlanningOptions,
    tube: VirtualTube | None = None,
) -> dict[str, float]:
    """(p1) for the plan interpolated as used: exact integrals of w and of mu (rho - rho_d)^2 (piecewise linear);
    with ``options.objective = 'last_out'`` also the swarm's half-extents over the speed at the entrance and the exit,
    ``entry_s`` and ``exit_s`` (`last_out.last_out_terms`, which needs the ``tube``)."""
    dl = np.diff(l_m)
    w = 1.0 / speed_mps
    e = density - swarm.rho_d_per_m2
    time_s = float(np.sum(0.5 * dl * (w[:-1] + w[1:])))
    dens = float(options.density_weight * np.sum(dl / 3.0 * (e[:-1] ** 2 + e[:-1] * e[1:] + e[1:] ** 2)))
    if options.objective == 'centre':
        return {'time_s': time_s, 'density': dens, 'total': time_s + dens}
    if tube is None:
        msg = "the last-robot-out objective needs the tube (its half-width at the plan's ends)"
        raise ValueError(msg)
    ends = last_out_terms(tube, swarm, l_m, speed_mps, density)
    return {'time_s': time_s, **ends, 'density': dens, 'total': time_s + ends['entry_s'] + ends['exit_s'] + dens}


def certify(
    tube: VirtualTube,
    swarm: SwarmParams,
    options: PlanningOptions,
    l_m: FloatArray,
    speed_mps: FloatArray,
    density: FloatArray,
) -> tuple[dict[str, float], dict[str, BoolArray]]:
    """Relative violations of (p2)-(p7) and of the initial values on a 10x finer grid, and the active sets.

    Violations are divided by the constraint's own bound (v_min or v_max, a_v, sqrt(a_n r_t), rho_max, a_rho,
    the initial value). Between fine points the plan is piecewise linear in w and rho, so rates are exact per
    fine interval and (p3), (p6) use the interval's largest speed. A relaxed plan is held to a_v and a_n as
    `planned_limits` raises them.
    """
    swarm = planned_limits(swarm, options)
    excess, change = _excess(tube, swarm, options, l_m, speed_mps, density)
    certificate = {name: _worst(values) for name, (values, _) in excess.items()}
    v0, rho0 = initial_conditions(swarm, options)
    certificate['initial'] = max(abs(speed_mps[0] - v0) / v0, abs(density[0] - rho0) / rho0)
    return certificate, _active_sets(tube, swarm, options, l_m, speed_mps, density, change)


def worst_places(
    tube: VirtualTube,
    swarm: SwarmParams,
    options: PlanningOptions,
    l_m: FloatArray,
    speed_mps: FloatArray,
    density: FloatArray,
) -> dict[str, float]:
    """Where each certificate entry is worst: the arc length (m) of the largest relative violation of (p2)-(p7)
    on the certificate's fine grid (an interval's start for the rates (p3), (p6)), 0 for the initial values and
    NaN for a constraint with no point to evaluate (p4 on a straight tube)."""
    excess, _ = _excess(tube, planned_limits(swarm, options), options, l_m, speed_mps, density)
    places = {name: float(at[np.argmax(values)]) if values.size else np.nan for name, (values, at) in excess.items()}
    return places | {'initial': 0.0}


def _worst(values: FloatArray) -> float:
    """The largest entry, at least 0 (0 for none)."""
    return float(max(0.0, np.max(values))) if values.size else 0.0


def _excess(
    tube: VirtualTube,
    swarm: SwarmParams,
    options: PlanningOptions,
    l_m: FloatArray,
    speed_mps: FloatArray,
    density: FloatArray,
) -> tuple[dict[str, tuple[FloatArray, FloatArray]], FloatArray]:
    """The relative excess of (p2)-(p7) over their bounds (> 0: violated) on the certificate's fine grid, each
    with the arc lengths it is evaluated at (points, or the intervals' starts for the rates), and |rho_f / rho - 1|
    on that grid."""
    fine = np.interp(np.linspace(0.0, l_m.size - 1, FINE_FACTOR * (l_m.size - 1) + 1), np.arange(l_m.size), l_m)
    w = np.interp(fine, l_m, 1.0 / speed_mps)
    rho = np.interp(fine, l_m, density)
    rho_f = predicted_density(tube, fine, rho, swarm.n_robots, options.lookahead_m, options.predictive_model)
    v = 1.0 / w
    dl = np.diff(fine)
    v_top = np.maximum(v[:-1], v[1:])
    a_rho = swarm.a_rho
    limit = curvature_speed_limit(tube, swarm, fine)
    curved = np.isfinite(limit)
    excess = {
        'p2': (np.maximum((swarm.v_min_mps - v) / swarm.v_min_mps, (v - swarm.v_max_mps) / swarm.v_max_mps), fine),
        'p3': ((np.abs(np.diff(w)) / dl / np.minimum(w[:-1], w[1:]) ** 3 - swarm.a_v_mps2) / swarm.a_v_mps2, fine[:-1]),
        'p4': ((v[curved] - limit[curved]) / limit[curved], fine[curved]),
        'p5': (
            np.maximum((rho - swarm.rho_max_per_m2) / swarm.rho_max_per_m2, (RHO_EPSILON - rho) / swarm.rho_max_per_m2),
            fine,
        ),
        'p6': ((np.abs(np.diff(rho)) / dl * v_top - a_rho) / a_rho, fine[:-1]),
        'p7': ((np.abs(rho_f - rho) / options.lookahead_m * v - a_rho) / a_rho, fine),
    }
    if options.braking_room:
        excess['braking'] = (braking_excess(swarm, v, rho), fine[:-1])
    return excess, np.abs(rho_f / rho - 1.0)


def _active_sets(
    tube: VirtualTube,
    swarm: SwarmParams,
    options: PlanningOptions,
    l_m: FloatArray,
    speed_mps: FloatArray,
    density: FloatArray,
    change: FloatArray,
) -> dict[str, BoolArray]:
    """Where each constraint binds at the grid points; ``change`` is |rho_f / rho - 1| on the fine grid."""
    w_nodes = 1.0 / speed_mps
    node_limit = curvature_speed_limit(tube, swarm, l_m)
    d_w = np.abs(np.diff(w_nodes)) / np.diff(l_m) / np.minimum(w_nodes[:-1], w_nodes[1:]) ** 3
    d_rho = np.abs(np.diff(density)) / np.diff(l_m) * np.maximum(speed_mps[:-1], speed_mps[1:])
    # (p7) as the planner imposes it: the interval's largest relative change times its largest rho and v
    blocks = change[:-1].reshape(l_m.size - 1, FINE_FACTOR).max(axis=1)
    change_max = np.maximum(blocks, change[FINE_FACTOR::FINE_FACTOR])
    p7_rate = change_max * np.maximum(density[:-1], density[1:]) * np.maximum(speed_mps[:-1], speed_mps[1:])
    tol = ACTIVE_RTOL
    return {
        'v_max': speed_mps >= swarm.v_max_mps * (1 - tol),
        'v_min': speed_mps <= swarm.v_min_mps * (1 + tol),
        'p3': _on_nodes(d_w >= swarm.a_v_mps2 * (1 - tol)),
        'p4': speed_mps >= node_limit * (1 - tol),
        'p6': _on_nodes(d_rho >= swarm.a_rho * (1 - tol)),
        'p7': _on_nodes(p7_rate / options.lookahead_m >= swarm.a_rho * (1 - tol)),
    }


def _on_nodes(per_interval: BoolArray) -> BoolArray:
    """A per-interval flag on both grid points of its interval."""
    on: BoolArray = np.concatenate([per_interval, [False]]) | np.concatenate([[False], per_interval])
    return on
