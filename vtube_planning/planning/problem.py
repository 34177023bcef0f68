"""The discretised planning problem: the arc-length grid, each interval's data, and a proof of feasibility.

Unknowns on an arc-length grid l_0..l_K: the slowness w = 1/v and the density rho, both interpolated linearly
between grid points. Each constraint is imposed so that it holds on every interval, not only at the grid points
(``docs/theory.md`` §8.1); the interval-wise data it needs is computed here, from ``SUBSAMPLES`` samples of each
interval. Infeasibility that can be known before a solver runs is reported with the constraint and the arc length.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import PlanError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.params import PlanningOptions, SwarmParams
from vtube_planning.planning.braking import braking_excess
from vtube_planning.planning.constraints import RHO_EPSILON, curvature_speed_limit, initial_conditions, planned_limits

FloatArray = NDArray[np.float64]

SUBSAMPLES = 20
"""Samples per grid interval used to bound curvature and width ratios over the interval."""
MAX_INTERVALS = 20_000
"""The finest grid planned: 20,000 intervals (a 0.003 m step on scenes A-D, whose default grid has 240)."""


@dataclass(frozen=True)
class Problem:
    """The discretised planning problem: grid, interval-wise data, boundary values, a feasible start."""

    tube: VirtualTube
    swarm: SwarmParams
    options: PlanningOptions
    l_m: FloatArray
    speed_cap_mps: FloatArray
    width_ratio: FloatArray
    v0_mps: float
    rho0_per_m2: float
    w_start: FloatArray
    rho_start: FloatArray

    @property
    def dl_m(self) -> FloatArray:
        """Lengths of the grid intervals, (K,)."""
        return np.diff(self.l_m)


def uniform_grid(length_m: float, step_m: float) -> FloatArray:
    """The planning grid: equal intervals of at most ``step_m`` from 0 to ``length_m`` (or
    [`PlanError`][vtube_planning.errors.PlanError])."""
    n_int = max(2, math.ceil(length_m / step_m - 1e-9))
    if n_int > MAX_INTERVALS:
        msg = (
            f'a grid step of {step_m:g} m makes {n_int:,} intervals on this {length_m:g} m tube, more '
            f'than the {MAX_INTERVALS:,} the planner takes (each is a few variables and constraints of every QP); '
            f'use a grid step of at least {length_m / MAX_INTERVALS:.3g} m.'
        )
        raise PlanError(msg)
    return np.linspace(0.0, length_m, n_int + 1)


def refined_grid(l_m: FloatArray, active: Mapping[str, NDArray[np.bool_]], factor: int) -> FloatArray:
    """``l_m`` with every interval next to a grid point where (p3), (p4), (p6) or (p7) binds split into ``factor``."""
    binds = active['p3'] | active['p4'] | active['p6'] | active['p7']
    split = binds[:-1] | binds[1:]
    parts = np.where(split, factor, 1)
    pieces = [np.linspace(a, b, count + 1)[:-1] for a, b, count in zip(l_m[:-1], l_m[1:], parts, strict=True)]
    return np.concatenate([*pieces, l_m[-1:]])


def discretise(
    tube: VirtualTube, swarm: SwarmParams, options: PlanningOptions, l_m: FloatArray | None = None
) -> Problem:
    """Build the grid and the interval-wise data, and prove feasibility (or raise
    [`PlanError`][vtube_planning.errors.PlanError]).

    The grid is ``options.grid_step_m`` uniform unless ``l_m`` (increasing, from 0 to the tube's length) is given.

    The slowest admissible speed profile (decelerate at a_v from v_0 down to v_min) and the fastest admissible
    expansion along it (density falling at a_rho until rho_epsilon) are the most permissive choices for every
    other constraint; if they violate one, the problem is infeasible there, and the message says where. The
    problem holds the swarm as `planned_limits` has it (a relaxed plan's a_v and a_n raised).
    """
    swarm = planned_limits(swarm, options)
    if l_m is None:
        l_m = uniform_grid(tube.length_m, options.grid_step_m)
    sub = np.linspace(l_m[:-1], l_m[1:], SUBSAMPLES + 1, axis=1)  # (K, S+1) samples of each interval
    speed_cap = _speed_cap(tube, swarm, l_m, sub)
    lam = tube.half_width(sub.ravel())
    lam_ahead = tube.half_width(sub.ravel() + options.lookahead_m)
    width_ratio = np.abs(lam / lam_ahead - 1.0).reshape(sub.shape).max(axis=1)
    v0, rho0 = initial_conditions(swarm, options)
    _check_boundary_values(swarm, v0, rho0, float(speed_cap[0]))
    _check_curvature_limit(swarm, l_m, speed_cap)
    w_start = _slowest_slowness(swarm, v0, l_m, speed_cap)
    rho_start = fastest_expansion(swarm, rho0, w_start, np.diff(l_m))
    problem = Problem(tube, swarm, options, l_m, speed_cap, width_ratio, v0, rho0, w_start, rho_start)
    if options.predictive_model == 'local_width':
        _check_local_width(problem)
    if options.braking_room:
        _check_braking(problem)
    return problem


def fastest_expansion(swarm: SwarmParams, rho0: float, w: FloatArray, dl: FloatArray) -> FloatArray:
    """Density falling as fast as (p6) allows along the slowness profile w, down to rho_epsilon."""
    rho = np.empty_like(w)
    rho[0] = rho0
    step = swarm.a_rho * dl * np.minimum(w[:-1], w[1:])
    for k in range(w.size - 1):
        rho[k + 1] = max(RHO_EPSILON, rho[k] - step[k])
    return rho


def _speed_cap(tube: VirtualTube, swarm: SwarmParams, l_m: FloatArray, sub: FloatArray) -> FloatArray:
    """The speed bound of each grid point, (K+1,): v_max and the curvature limit (p4) over both intervals around it
    (``sub``: each interval's samples, (K, S+1)), both sides of every joint of the centre line included."""
    length = tube.length_m
    n_int = l_m.size - 1
    inside = tube.center.breakpoints[(tube.center.breakpoints > 0) & (tube.center.breakpoints < length)]
    limit_sub = curvature_speed_limit(tube, swarm, sub.ravel()).reshape(sub.shape).min(axis=1)
    if inside.size:  # curvature jumps at the joints of arcs: include both sides
        joint_k = np.clip(np.searchsorted(l_m, inside) - 1, 0, n_int - 1)
        eps = 1e-9 * max(1.0, length)
        joint = np.minimum(
            curvature_speed_limit(tube, swarm, inside - eps), curvature_speed_limit(tube, swarm, inside + eps)
        )
        np.minimum.at(limit_sub, joint_k, joint)
    interval_cap = np.minimum(limit_sub, swarm.v_max_mps)
    cap: FloatArray = np.minimum(np.concatenate([interval_cap, [np.inf]]), np.concatenate([[np.inf], interval_cap]))
    return cap


def _slowest_slowness(swarm: SwarmParams, v0: float, l_m: FloatArray, speed_cap: FloatArray) -> FloatArray:
    """The slowest admissible profile: from v_0, brake as hard as (p3) allows down to v_min;
    [`PlanError`][vtube_planning.errors.PlanError] where it is still faster than the speed cap."""
    dl = np.diff(l_m)
    w_start = np.empty_like(l_m)
    w_start[0] = 1.0 / v0
    for k in range(l_m.size - 1):  # decelerate as hard as (p3) allows, |dw| <= a_v dl w_k^3 while w increases
        w_start[k + 1] = min(1.0 / swarm.v_min_mps, w_start[k] + swarm.a_v_mps2 * dl[k] * w_start[k] ** 3)
    too_fast = np.flatnonzero(w_start * speed_cap < 1.0 - 1e-12)
    if too_fast.size:
        k = int(too_fast[0])
        msg = (
            f'(p3) and (p4) conflict at l = {l_m[k]:.3f} m: starting at v_0 = {v0:g} m/s and braking at '
            f'a_v = {swarm.a_v_mps2:g} m/s^2 the swarm still moves at {1 / w_start[k]:.4g} m/s where the curvature '
            f'allows {speed_cap[k]:.4g} m/s; start slower (planning v0_mps) or move the turn further in.'
        )
        raise PlanError(msg)
    return w_start


def _check_boundary_values(swarm: SwarmParams, v0: float, rho0: float, cap0: float) -> None:
    """[`PlanError`][vtube_planning.errors.PlanError] unless the initial speed and density satisfy (p2), (p4) and (p5)
    at the entrance."""
    if not swarm.v_min_mps <= v0 <= swarm.v_max_mps:
        msg = f'(p2) fails at l = 0: v0_mps = {v0:g} lies outside [v_min, v_max] = [{swarm.v_min_mps:g}, {swarm.v_max_mps:g}].'
        raise PlanError(msg)
    if v0 > cap0 * (1 + 1e-12):
        msg = f'(p4) fails at l = 0: v0_mps = {v0:g} exceeds the curvature limit {cap0:.4g} m/s at the entrance.'
        raise PlanError(msg)
    if not RHO_EPSILON <= rho0 <= swarm.rho_max_per_m2:
        msg = (
            f'(p5) fails at l = 0: the initial density {rho0:g} robots/m^2 lies outside [{RHO_EPSILON:g}, '
            f'rho_max = {swarm.rho_max_per_m2:g}]; set planning rho0_per_m2 or raise rho_max_per_m2.'
        )
        raise PlanError(msg)


def _check_curvature_limit(swarm: SwarmParams, l_m: FloatArray, speed_cap: FloatArray) -> None:
    """[`PlanError`][vtube_planning.errors.PlanError] where the curvature limit (p4) lies below v_min (p2)."""
    low = np.flatnonzero(speed_cap < swarm.v_min_mps * (1 - 1e-12))
    if low.size:
        k = int(low[0])
        msg = (
            f'(p4) is incompatible with (p2) at l = {l_m[k]:.3f} m: the curvature limit sqrt(a_n r_t) = '
            f'{speed_cap[k]:.4g} m/s is below v_min = {swarm.v_min_mps:g} m/s (r_t = {speed_cap[k] ** 2 / swarm.a_n_mps2:.4g} m); '
            f'widen the turn to r_t >= v_min^2 / a_n = {swarm.v_min_mps**2 / swarm.a_n_mps2:.4g} m or lower v_min.'
        )
        raise PlanError(msg)


def _check_local_width(problem: Problem) -> None:
    """[`PlanError`][vtube_planning.errors.PlanError] where the local-width (p7) fails even on the slowest start
    expanding as fast as it may."""
    swarm, options = problem.swarm, problem.options
    budget = swarm.a_rho * options.lookahead_m * np.minimum(problem.w_start[:-1], problem.w_start[1:])
    need = problem.width_ratio * np.maximum(problem.rho_start[:-1], problem.rho_start[1:])
    bad = np.flatnonzero(need > budget * (1 + 1e-12))
    if bad.size:
        k = int(bad[0])
        msg = (
            f'(p7) cannot hold at l = {problem.l_m[k]:.3f} m: even at v_min, expanding as fast as (p6) allows, the '
            f'density {max(problem.rho_start[k], problem.rho_start[k + 1]):.4g} robots/m^2 meets a width ratio '
            f'{problem.width_ratio[k]:.3g} over the look-ahead {options.lookahead_m:g} m; start at a lower density, '
            'make the narrowing start later or more gradual, or lengthen lookahead_m.'
        )
        raise PlanError(msg)


def _check_braking(problem: Problem) -> None:
    """[`PlanError`][vtube_planning.errors.PlanError] where the room for braking fails even on the slowest start
    expanding as fast as it may."""
    swarm = problem.swarm
    bad = np.flatnonzero(braking_excess(swarm, 1.0 / problem.w_start, problem.rho_start) > 1e-12)
    if bad.size:
        k = int(bad[0])
        msg = (
            f'the room for braking cannot hold at l = {problem.l_m[k]:.3f} m: even braking from v_0 to v_min and '
            f'expanding as fast as (p6) allows, the spacing at {max(problem.rho_start[k], problem.rho_start[k + 1]):.4g} '
            'robots/m^2 is shorter than 2 r_s plus the braking distance; start slower or at a lower density, or plan '
            'without braking_room.'
        )
        raise PlanError(msg)
