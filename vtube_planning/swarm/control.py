"""The distributed swarm controller of the paper (eq. s1 and a3), vectorised over the swarm.

Every robot i at p_i, projected onto the tube (arc length l_i, tangent t_c, left normal n, offset y_i), commands
(``theory.md`` §2.8)::

    v_c,i = sat(v_f,i + v_m,i(r_a,i) + v_xy,i(r_a,i), v_min, v_max)
    v_f,i  = v*(l_i) t_c                                        forward term (the plan, or a constant speed)
    v_m,i  = sum_j phi_m(|p_ij|; r_a,i) p_ij / |p_ij|            inter-robot avoidance, p_ij = p_i - p_j
    v_xy,i = -phi_t(d_i; r_a,i) sign(y_i) n,  d_i = lambda(l_i) - |y_i|   tube keeping (normal-only gradient)

with the magnitudes of the *barrier* law (default), phi = -dV/dx of the Lyapunov-like barriers V_m, V_t of
``theory.md`` §2.4 with sigma(x, 2 r_s, r_s + r_a,i) and sigma(d, r_s, r_a,i), or of the *practical* law of
[b17], phi_m = k_m sigma(x, 2 r_s, r_s + r_a,i) and phi_t = k_t sigma(d, r_s, r_a,i). Both grow with r_a,i,
the seed's expansion knob. The barrier law is the default because it is the one that keeps the expanding swarm
inside the tube: the practical law's wall push is bounded by k_t while the pushes of the neighbours add up, and
once r_a exceeds the narrow half-width its wall band covers the whole section (measured on scenes A-D: tube
violations with k_t = 5, collisions and congestion with k_t = 15 or 40). sat rescales radially into [v_min, v_max]
(faithful, A10); a zero vector becomes v_min t_c. The avoidance radius follows (a3),
``r_a,i' = k_ra max(0, rho_r - rho*(l_i))`` with the global density rho_r (A8), capped at ``r_a_max`` (A9),
optionally floored by the feed-forward ``1/sqrt(rho*) - r_s`` of §2.8.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from vtube_planning._validate import as_points, is_positive
from vtube_planning.errors import ParamsError
from vtube_planning.params import SwarmParams
from vtube_planning.geometry.tube import Projection, VirtualTube

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]

LAWS = ('practical', 'barrier')
BARRIER_EPS = 1e-6
"""epsilon_m = epsilon_t = epsilon_s of the barrier functions (the group's code, ``theory.md`` §2.5)."""


# ---------------------------------------------------------------------- scalar building blocks (theory.md §2.3)


def sigma(x: FloatArray, d1: FloatArray | float, d2: FloatArray | float) -> tuple[FloatArray, FloatArray]:
    """The C^1 cubic step sigma(x, d1, d2): 1 for x <= d1, 0 for x >= d2; returns (value, d/dx)."""
    x = np.asarray(x, dtype=float)
    d1 = np.broadcast_to(np.asarray(d1, dtype=float), x.shape)
    d2 = np.broadcast_to(np.asarray(d2, dtype=float), x.shape)
    t = np.clip((x - d1) / (d2 - d1), 0.0, 1.0)
    inside = (x > d1) & (x < d2)
    value = 1.0 - t * t * (3.0 - 2.0 * t)
    slope = np.where(inside, -6.0 * t * (1.0 - t) / (d2 - d1), 0.0)
    return value, slope


def smooth_saturation(x: FloatArray, eps: float) -> tuple[FloatArray, FloatArray]:
    """The C^1 saturation s(x, eps) of ``theory.md`` §2.3 (x below x1, a circular arc, then 1); (value, d/dx)."""
    x = np.asarray(x, dtype=float)
    x2 = 1.0 + eps / math.tan(math.radians(67.5))
    x1 = x2 - eps * math.sin(math.radians(45.0))
    arc = (x > x1) & (x < x2)
    root = np.sqrt(np.clip(eps**2 - (x - x2) ** 2, 0.0, None))
    value = np.where(x <= x1, x, np.where(x >= x2, 1.0, (1.0 - eps) + root))
    with np.errstate(divide='ignore', invalid='ignore'):
        slope = np.where(x <= x1, 1.0, np.where(arc, (x2 - x) / root, 0.0))
    return value, slope


def barrier_gain(x: FloatArray, offset: float, d1: float, d2: FloatArray, k: float) -> FloatArray:
    """-dV/dx of the barrier V = k sigma(x, d1, d2) / ((1 + eps) x - offset s(x / offset, eps)), ``theory.md`` §2.4.

    ``offset`` is 2 r_s between robots (d1 = 2 r_s) and r_s at the wall (d1 = r_s). Non-negative; huge (about
    k / (eps x^2)) inside the safety distance, zero beyond d2.
    """
    x = np.maximum(np.asarray(x, dtype=float), 1e-9)
    s_val, s_slope = smooth_saturation(x / offset, BARRIER_EPS)
    den = (1.0 + BARRIER_EPS) * x - offset * s_val
    sig, sig_slope = sigma(x, d1, d2)
    dv = k * (sig_slope / den - sig * ((1.0 + BARRIER_EPS) - s_slope) / den**2)
    return np.maximum(-dv, 0.0)


def saturate(u: FloatArray, v_min: float, v_max: float, fallback: FloatArray) -> FloatArray:
    """sat(u, v_min, v_max) column-wise on (2, N): radial rescaling into [v_min, v_max]; u = 0 -> v_min fallback."""
    speed = np.hypot(u[0], u[1])
    zero = speed <= 1e-12
    scale = np.where(zero, 0.0, np.clip(speed, v_min, v_max) / np.where(zero, 1.0, speed))
    return np.where(zero, v_min * fallback, u * scale)


# ---------------------------------------------------------------------- parameters


@dataclass(frozen=True)
class ControlParams:
    """Gains and options of the swarm controller.

    Parameters
    ----------
    avoidance_gain, keeping_gain
        Gains k of the inter-robot avoidance and tube-keeping terms: m^3/s in the barrier law (V = k sigma / D,
        the group's code uses 1), m/s in the practical law (its largest push per neighbour or wall).
    k_ra_m3ps
        Gain of the avoidance-radius law (a3), m/s per robot/m^2.
    r_a_max_m
        Cap of the avoidance radius (resolution A9); None means three times the initial r_a.
    feedforward
        Floor r_a,i by 1/sqrt(rho*(l_i)) - r_s, the lattice spacing that realises the planned density (§2.8).
    law
        ``'practical'`` (sigma-weighted, bounded) or ``'barrier'`` (gradients of the barrier functions).
    kdtree_above
        Use a k-d tree for neighbours above this many robots, all pairs below.
    """

    avoidance_gain: float = 1.0
    keeping_gain: float = 1.0
    k_ra_m3ps: float = 5.0
    r_a_max_m: float | None = None
    feedforward: bool = False
    law: str = 'barrier'
    kdtree_above: int = 48

    def __post_init__(self) -> None:
        for name in ('avoidance_gain', 'keeping_gain', 'k_ra_m3ps'):
            if not is_positive(getattr(self, name)):
                msg = f'control {name} must be a finite number > 0; got {getattr(self, name)!r}.'
                raise ParamsError(msg)
        if self.r_a_max_m is not None and not is_positive(self.r_a_max_m):
            msg = f'control r_a_max_m must be a finite number > 0 or omitted; got {self.r_a_max_m!r}.'
            raise ParamsError(msg)
        if self.law not in LAWS:
            msg = f'control law must be one of {LAWS}; got {self.law!r}.'
            raise ParamsError(msg)
        if not isinstance(self.feedforward, bool):
            msg = f'control feedforward must be true or false; got {self.feedforward!r}.'
            raise ParamsError(msg)
        if isinstance(self.kdtree_above, bool) or not isinstance(self.kdtree_above, int) or self.kdtree_above < 0:
            msg = f'control kdtree_above must be an integer >= 0; got {self.kdtree_above!r}.'
            raise ParamsError(msg)

    def radius_cap(self, swarm: SwarmParams) -> float:
        """The largest avoidance radius, m."""
        cap = 3.0 * swarm.r_a_m if self.r_a_max_m is None else float(self.r_a_max_m)
        if cap < swarm.r_a_m:
            msg = f'control r_a_max_m ({cap}) is below the initial avoidance radius r_a_m ({swarm.r_a_m}); raise it.'
            raise ParamsError(msg)
        return cap


# ---------------------------------------------------------------------- the law


def neighbour_pairs(positions: FloatArray, radius: float, *, use_tree: bool) -> tuple[IntArray, IntArray, FloatArray]:
    """Pairs (i < j) of columns of (2, N) positions closer than ``radius``, and their distances."""
    n = positions.shape[1]
    if use_tree:
        pairs = cKDTree(positions.T).query_pairs(radius, output_type='ndarray')
        i, j = pairs[:, 0], pairs[:, 1]
    else:
        i, j = np.triu_indices(n, k=1)
    dist = np.hypot(positions[0, i] - positions[0, j], positions[1, i] - positions[1, j])
    keep = dist < radius
    return i[keep], j[keep], dist[keep]


def avoidance_velocity(positions: FloatArray, r_a: FloatArray, swarm: SwarmParams, params: ControlParams) -> FloatArray:
    """v_m of every robot, (2, N): the sum over neighbours closer than r_s + r_a,i of phi_m times the unit p_ij."""
    n = positions.shape[1]
    out = np.zeros_like(positions)
    if n < 2:
        return out
    r_s = swarm.r_s_m
    i, j, dist = neighbour_pairs(positions, r_s + float(r_a.max()), use_tree=n > params.kdtree_above)
    if i.size == 0:
        return out
    unit = (positions[:, i] - positions[:, j]) / np.maximum(dist, 1e-12)  # from j to i
    for me, other_sign, radius in ((i, 1.0, r_a[i]), (j, -1.0, r_a[j])):
        if params.law == 'practical':
            gain = params.avoidance_gain * sigma(dist, 2.0 * r_s, r_s + radius)[0]
        else:
            gain = barrier_gain(dist, 2.0 * r_s, 2.0 * r_s, r_s + radius, params.avoidance_gain)
        push = other_sign * gain * unit
        out[0] += np.bincount(me, weights=push[0], minlength=n)
        out[1] += np.bincount(me, weights=push[1], minlength=n)
    return out


def tube_keeping_velocity(projection: Projection, r_a: FloatArray, swarm: SwarmParams,
                          params: ControlParams) -> FloatArray:
    """v_xy of every robot, (2, N): phi_t(d_i) towards the centre line along the normal."""
    d = projection.clearance_m
    r_s = swarm.r_s_m
    if params.law == 'practical':
        gain = params.keeping_gain * sigma(d, r_s, r_a)[0]
    else:
        gain = barrier_gain(d, r_s, r_s, r_a, params.keeping_gain)
    return -gain * np.sign(projection.y_m) * projection.normal


@dataclass(frozen=True)
class Command:
    """One evaluation of the controller: the saturated command and its parts, (2, N) each."""

    velocity: FloatArray
    forward: FloatArray
    avoidance: FloatArray
    tube_keeping: FloatArray
    projection: Projection


def velocity_command(positions: FloatArray, r_a: FloatArray, forward_speed_mps: FloatArray, tube: VirtualTube,
                     swarm: SwarmParams, params: ControlParams, projection: Projection | None = None) -> Command:
    """The command v_c of every robot (eq. s1).

    Parameters
    ----------
    positions
        Robot positions, (2, N).
    r_a
        Avoidance radii r_a,i, (N,).
    forward_speed_mps
        v*(l_i) of every robot, (N,) (the plan at its arc length, or a constant without planning).
    projection
        The positions' projection onto the tube, when the caller already has it.
    """
    check_positions(positions)
    if projection is None:
        projection = tube.project(positions)
    forward = forward_speed_mps * projection.tangent
    avoidance = avoidance_velocity(positions, r_a, swarm, params)
    keeping = tube_keeping_velocity(projection, r_a, swarm, params)
    velocity = saturate(forward + avoidance + keeping, swarm.v_min_mps, swarm.v_max_mps, projection.tangent)
    return Command(velocity, forward, avoidance, keeping, projection)


def avoidance_radius_rate(rho_measured: float, rho_planned: FloatArray, params: ControlParams) -> FloatArray:
    """(a3): r_a,i' = k_ra max(0, rho_r - rho*(l_i)), m/s, (N,)."""
    return params.k_ra_m3ps * np.maximum(0.0, rho_measured - np.asarray(rho_planned, dtype=float))


def feedforward_radius(rho_planned: FloatArray, swarm: SwarmParams) -> FloatArray:
    """1/sqrt(rho*) - r_s: the avoidance radius whose lattice (spacing r_s + r_a) has density rho*, (N,)."""
    return 1.0 / np.sqrt(np.asarray(rho_planned, dtype=float)) - swarm.r_s_m


def check_positions(positions: FloatArray) -> None:
    """Raise :class:`ShapeError` unless positions are finite and (2, N) with N >= 1."""
    as_points(positions, name='positions', item='robots', min_count=1)
