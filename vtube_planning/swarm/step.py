"""One control period of the swarm: everything a robot does, given the swarm's state. One implementation.

The simulator (:mod:`vtube_planning.swarm.simulate`), the bundled Robotarium experiment
(:mod:`robotarium_exp.experiment`) and the file submitted to the testbed (:mod:`submission.builder` inlines this
module's source) all call :class:`SwarmStep`. It needs numpy and scipy only, which the testbed has.

Every robot i at p_i, projected onto the tube (arc length l_i, tangent t_c, left normal n, offset y_i), commands
(eq. s1, ``docs/theory.md`` §2.8)::

    v_c,i = sat(v_f,i + v_m,i(r_a,i) + v_xy,i(r_a,i), v_min, v_max)
    v_f,i  = v*(l_i) t_c                                        forward term (the plan, or a constant speed)
    v_m,i  = sum_j phi_m(|p_ij|; r_a,i) p_ij / |p_ij|            inter-robot avoidance, p_ij = p_i - p_j
    v_xy,i = -phi_t(d_i; r_a,i) sign(y_i) n,  d_i = lambda(l_i) - |y_i|   tube keeping (normal-only gradient)

or, with ``saturation = 'forward'``, ``v_c,i = cap(v_f,i + sat(v_m,i + v_xy,i, v*(l_i) - v_min), v_max)`` (the
forward-progress form of ``docs/theory.md`` §2.7: the forward component never drops below v_min), with the
magnitudes of the *barrier* law (default), phi = -dV/dx of the Lyapunov-like barriers V_m, V_t of
``docs/theory.md`` §2.4 with sigma(x, 2 r_s, r_s + r_a,i) and sigma(d, r_s, r_a,i), or of the *practical* law
of [b17], phi_m = k_m sigma(x, 2 r_s, r_s + r_a,i) and phi_t = k_t sigma(d, r_s, r_a,i). sat rescales radially
into [v_min, v_max] (faithful, A10); a zero vector becomes v_min t_c.

The swarm's density is measured once per step (:func:`swarm_density`, the one definition, A7-A8), and with a plan
the avoidance radius follows (a3), ``r_a,i' = k_ra max(0, rho_r - rho*(l_i))``, capped at ``r_a_max`` (A9),
optionally floored by the feed-forward ``1/sqrt(rho*) - r_s`` (§2.8). Robots past the exit either keep flying
the law (the paper's study) or, given parking slots (the Robotarium, where the arena ends), drive to the next
free slot beyond the exit and leave the swarm: its avoidance and its density count only the robots still flying
the tube (the safety filter keeps everyone apart).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]

LAWS = ('practical', 'barrier')
DENSITY_PADDINGS = ('initial', 'current')
"""How far the measured footprint extends beyond the last and the front robot: the initial r_a (fixed cells of
Assumption 2, A7), or the swarm's current mean r_a (cells that grow with (a3))."""
SATURATIONS = ('radial', 'forward')
"""How the command meets the speed band: the paper's radial sat of the whole sum (A10: it can point backwards), or
the forward-progress form v* t_c + sat(v_m + v_xy, v* - v_min) capped at v_max (``docs/theory.md`` §2.7), which
keeps every robot moving forward at v_min or more."""
PLAN_AT = ('robot', 'center')
"""Where every robot reads the plan: at its own arc length l_i, or at the swarm centre's (``docs/theory.md`` A16)."""
BARRIER_EPS = 1e-6
"""epsilon_m = epsilon_t = epsilon_s of the barrier functions (the group's code, ``docs/theory.md`` §2.5)."""
PARKED_WITHIN_M = 0.03
"""A robot is parked when its control point is this close to its slot."""
KDTREE_ABOVE = 64
"""Swarms of more robots find their neighbours with a k-d tree, smaller ones test all pairs.

Measured: ``python -m benchmarks.sim_bench`` times the avoidance term (neighbour search and phi_m) both ways on
its jittered crowd of about one robot per m^2 (2-core VM, numpy 2, scipy's cKDTree): all pairs 0.085 / 0.096 /
0.107 ms at N = 50 / 60 / 70, the tree 0.103 / 0.109 / 0.111 ms; at N = 80 all pairs 0.120 ms, the tree 0.113 ms.
The crossover lies between 70 and 80 robots; near it the two differ by under 10 %, so its exact place matters
little (and keeping 64 keeps every swarm on the path, and the sums in the order, it had before)."""


# ---------------------------------------------------------------------- scalar building blocks (theory §2.3)


def sigma(x: ArrayLike, d1: ArrayLike, d2: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The C^1 cubic step sigma(x, d1, d2): 1 for x <= d1, 0 for x >= d2; returns (value, d/dx).

    Shapes broadcast. Written with few array operations, for the step calls it on a handful of robots every
    control period (its fixed cost per call matters there), and in place, for it also calls it on the hundreds of
    thousands of pairs of a large swarm (where every fresh array costs its page faults).
    """
    x = np.asarray(x, dtype=float)
    band: FloatArray = np.asarray(d2, dtype=float) - np.asarray(d1, dtype=float)
    t: FloatArray = np.divide(x - d1, band)
    np.maximum(t, 0.0, out=t)  # np.clip(t, 0, 1)'s values, without its call cost
    np.minimum(t, 1.0, out=t)
    value = 2.0 * t  # 1 - t t (3 - 2 t)
    np.subtract(3.0, value, out=value)
    value *= t * t
    np.subtract(1.0, value, out=value)
    slope = -6.0 * t  # -6 t (1 - t) / band: (-)0 outside (d1, d2), where t is clipped to 0 or 1
    np.subtract(1.0, t, out=t)
    slope *= t
    slope /= band
    return value, slope


def smooth_saturation(x: ArrayLike, eps: float) -> tuple[FloatArray, FloatArray]:
    """The C^1 saturation s(x, eps) of ``docs/theory.md`` §2.3 (x below x1, a circular arc, then 1); (value, d/dx).

    Below x1 = x2 - eps sin 45deg (< 1) s = x, above x2 = 1 + eps / tan 67.5deg (> 1) s = 1, so ``min(x, 1)`` is
    s outside the arc; the arc (width about 0.7 eps) is evaluated only where some x falls on it.
    """
    x = np.asarray(x, dtype=float)
    x1, x2 = _saturation_corners(eps)
    value = np.minimum(x, 1.0, out=np.empty(x.shape))  # an array also for a scalar x: written below
    slope = np.array(x <= x1, dtype=float)
    arc = (x > x1) & (x < x2)
    if arc.any():
        on_arc = x[arc]
        root = np.sqrt(np.maximum(eps**2 - (on_arc - x2) ** 2, 0.0))  # > 0 inside the arc
        value[arc] = (1.0 - eps) + root
        slope[arc] = (x2 - on_arc) / root
    return value, slope


@lru_cache(maxsize=4)
def _saturation_corners(eps: float) -> tuple[float, float]:
    """x1 and x2 of s(x, eps)."""
    x2 = 1.0 + eps / math.tan(math.radians(67.5))
    return x2 - eps * math.sin(math.radians(45.0)), x2


def barrier_gain(
    x: ArrayLike, offset: FloatArray | float, d1: FloatArray | float, d2: ArrayLike, k: FloatArray | float
) -> FloatArray:
    """-dV/dx of the barrier V = k sigma(x, d1, d2) / ((1 + eps) x - offset s(x / offset, eps)), theory §2.4.

    ``offset`` is 2 r_s between robots (d1 = 2 r_s) and r_s at the wall (d1 = r_s); each of them a number or an
    array like x, element by element. Non-negative; huge (about k / (eps x^2)) inside the safety distance, zero
    beyond d2.
    """
    xs = np.maximum(np.asarray(x, dtype=float), 1e-9)
    s_val, s_slope = smooth_saturation(xs / offset, BARRIER_EPS)
    den = (1.0 + BARRIER_EPS) * xs  # (1 + eps) x - offset s
    s_val *= offset
    den -= s_val
    sig, sig_slope = sigma(xs, d1, d2)
    # -dV/dx = -k (sigma' / den - sigma ((1 + eps) - s') / den^2), in place (see sigma)
    sig_slope /= den
    np.subtract(1.0 + BARRIER_EPS, s_slope, out=s_slope)
    sig *= s_slope
    np.square(den, out=den)
    sig /= den
    sig_slope -= sig
    sig_slope *= np.negative(k)
    return np.maximum(sig_slope, 0.0, out=sig_slope)


def cap_norm(u: FloatArray, limit: ArrayLike) -> FloatArray:
    """Columns of (2, N) ``u`` rescaled to a norm of at most ``limit`` (scalar or (N,)); shorter ones unchanged."""
    speed = np.hypot(u[0], u[1])
    limit = np.asarray(limit, dtype=float)
    return u * np.where(speed > limit, limit / np.maximum(speed, 1e-300), 1.0)


def saturate(u: FloatArray, v_min: float, v_max: float, fallback: FloatArray) -> FloatArray:
    """sat(u, v_min, v_max) column-wise on (2, N): radial rescaling into [v_min, v_max]; u = 0 -> v_min fallback."""
    speed = np.hypot(u[0], u[1])
    clipped = np.minimum(np.maximum(speed, v_min), v_max)
    if speed.min() > 1e-12:  # the usual case, in fewer array operations
        clipped /= speed
        return u * clipped
    zero = speed <= 1e-12
    scale = np.where(zero, 0.0, clipped / np.where(zero, 1.0, speed))
    return np.where(zero, v_min * fallback, u * scale)


# ---------------------------------------------------------------------- what the step is given


@dataclass(frozen=True)
class StepParams:
    """The numbers one control period needs (made and validated by ``ControlParams.step_params(swarm)``).

    Attributes
    ----------
    r_s_m
        Safety radius r_s.
    r_a_m
        Initial avoidance radius; also the padding of the density measure at both ends of the swarm (A7).
    r_a_max_m
        Cap of the avoidance radius (A9).
    v_min_mps, v_max_mps
        The speed band of sat.
    law
        ``'barrier'`` or ``'practical'``.
    saturation
        ``'radial'`` (the paper's sat) or ``'forward'`` (the forward-progress form), ``SATURATIONS``.
    density_padding
        Pad the measured footprint by the initial r_a or by the current mean r_a, ``DENSITY_PADDINGS``.
    avoidance_gain, keeping_gain
        Gains of the avoidance and tube-keeping terms.
    k_ra_m3ps
        Gain of (a3).
    feedforward
        Floor r_a by ``1/sqrt(rho*) - r_s``.
    plan_at
        ``'robot'``: every robot reads v* and rho* at its own arc length (the paper); ``'center'``: at the mean arc
        length of the swarm's robots, for which the plan is made (A16).
    kdtree_above
        Find neighbours with a k-d tree above this many robots, all pairs below.
    """

    r_s_m: float
    r_a_m: float
    r_a_max_m: float
    v_min_mps: float
    v_max_mps: float
    law: str = 'barrier'
    saturation: str = 'radial'
    density_padding: str = 'initial'
    avoidance_gain: float = 1.0
    keeping_gain: float = 1.0
    k_ra_m3ps: float = 5.0
    feedforward: bool = False
    plan_at: str = 'robot'
    kdtree_above: int = KDTREE_ABOVE


@dataclass(frozen=True)
class PlanProfile:
    """The plan as the controller uses it: slowness w = 1/v and density rho, both linear between grid points.

    Outside [0, L] the end values hold. ``Plan.speed`` and ``Plan.density`` are these functions.
    """

    l_m: FloatArray
    slowness_spm: FloatArray
    density_per_m2: FloatArray

    def speed(self, l_m: ArrayLike) -> FloatArray:
        """v*(l) = 1 / (linear interpolation of w), m/s."""
        return 1.0 / np.interp(np.asarray(l_m, dtype=float), self.l_m, self.slowness_spm)

    def density(self, l_m: ArrayLike) -> FloatArray:
        """rho*(l), linear interpolation, robots/m^2."""
        return np.interp(np.asarray(l_m, dtype=float), self.l_m, self.density_per_m2)


# ---------------------------------------------------------------------- the density measure (A7, A8)


def swarm_area(tube: Any, l_back_m: ArrayLike, l_front_m: ArrayLike, pad_m: float) -> FloatArray:
    """Area (m^2) of the tube between ``l_back - pad`` and ``l_front + pad``, element-wise (``tube.area``: A(l))."""
    front = np.asarray(l_front_m, dtype=float) + pad_m
    back = np.asarray(l_back_m, dtype=float) - pad_m
    if front.shape != back.shape:
        front, back = np.broadcast_arrays(front, back)
    ends = np.array([front, back]).reshape(2, -1)  # (2, k); scalars as k = 1
    area = np.asarray(tube.area(ends.ravel()), dtype=float).reshape(2, -1)  # one call: the step makes it each period
    return area[0] - area[1]


def swarm_density(tube: Any, l_m: ArrayLike, pad_m: float) -> float:
    """The swarm's density rho = N / S, robots/m^2: S is the tube's area between the last and the front robot's
    arc lengths ``l_m`` (N,), padded by ``pad_m`` (the initial r_a) at both ends so that a line-abreast swarm has
    a finite density (A7); one number for the whole swarm (A8).
    """
    l_m = np.asarray(l_m, dtype=float)
    if l_m.size == 0:
        msg = 'the swarm density needs at least one robot; got no arc lengths.'
        raise ValueError(msg)
    return float(l_m.size / swarm_area(tube, l_m.min(), l_m.max(), pad_m)[0])


# ---------------------------------------------------------------------- the law


def neighbour_pairs(positions: FloatArray, radius: float) -> tuple[IntArray, IntArray]:
    """Pairs (i, j), i < j, of columns of (2, N) positions at most ``radius`` apart, found with a k-d tree
    (O(N log N) time, memory of the order of the pairs found)."""
    # an unbalanced tree with uncompacted nodes builds about twice as fast (100,000 robots: 14 ms, not 31 ms)
    # and finds the same pairs: robots are spread evenly, the tree needs no balancing
    tree = cKDTree(positions.T, balanced_tree=False, compact_nodes=False)
    pairs = tree.query_pairs(radius, output_type='ndarray').T
    return np.ascontiguousarray(pairs[0]), np.ascontiguousarray(pairs[1])  # contiguous: gathered from below


@lru_cache(maxsize=8)
def _all_pairs(n: int) -> tuple[IntArray, IntArray, IntArray]:
    """(i, j), i < j, of all pairs of n robots and the robots their halves act on, [i, j] (read-only, kept for the
    next step of the same swarm)."""
    i, j = np.triu_indices(n, k=1)
    pairs = (i, j, np.concatenate([i, j]))
    for index in pairs:
        index.flags.writeable = False
    return pairs


def interaction_gains(
    pair_dist: FloatArray, pair_band: FloatArray, clearance: FloatArray, r_a: FloatArray, params: StepParams
) -> tuple[FloatArray, FloatArray]:
    """The magnitudes of (s1)'s two pushes: phi_m of pairs at distances ``pair_dist`` (M,) with bands r_s + r_a of
    the robot pushed, ``pair_band`` (M,), and phi_t of the walls at clearances ``clearance`` (K,) with bands ``r_a``
    (K,). Both in one evaluation of the law: its fixed cost per call dominates a small swarm's step."""
    m, k = pair_dist.size, clearance.size
    r_s = params.r_s_m
    x = np.concatenate([pair_dist, clearance])
    d2 = np.concatenate([pair_band, r_a])
    d1, gains = np.empty(m + k), np.empty(m + k)  # written slice by slice: cheaper than np.repeat on small arrays
    d1[:m], d1[m:] = 2.0 * r_s, r_s  # where the push saturates: 2 r_s between robots, r_s at walls
    gains[:m], gains[m:] = params.avoidance_gain, params.keeping_gain
    if params.law == 'practical':
        gain = gains * sigma(x, d1, d2)[0]
    else:
        gain = barrier_gain(x, d1, d1, d2, gains)
    return gain[:m], gain[m:]


_NONE = np.empty(0)
"""No pairs, or no walls, for :func:`interaction_gains` (read-only)."""
_NONE.flags.writeable = False


def _acting_halves(
    positions: FloatArray, r_a: FloatArray, params: StepParams, members: NDArray[np.bool_] | None
) -> tuple[IntArray, FloatArray, FloatArray, FloatArray]:
    """The halves of pairs that push (the robot pushed within r_s + r_a of the other): their bins in
    :func:`_summed_pushes`, p_pushed - p_other (2, M), distances (M,) and the pushed robots' bands r_s + r_a (M,).

    Up to ``params.kdtree_above`` robots every pair is tested, above them a k-d tree finds the pairs within
    r_s + max r_a (:data:`KDTREE_ABOVE`). Each pair (i, j) acts twice, once on i and once on j, each half within its
    robot's own band; beyond it phi_m is exactly 0, so such halves are dropped before phi_m is evaluated.
    """
    n = positions.shape[1]
    r_s = params.r_s_m
    if n < 2:
        return np.empty(0, dtype=np.intp), np.empty((2, 0)), _NONE, _NONE
    if n > params.kdtree_above:
        i, j = neighbour_pairs(positions, r_s + float(r_a.max()))
        me = np.concatenate([i, j])
    else:
        i, j, me = _all_pairs(n)
    diff = positions.take(i, axis=1)  # p_i - p_j
    diff -= positions.take(j, axis=1)
    dist = np.hypot(diff[0], diff[1])
    band = r_a.take(me).reshape(2, -1)  # the halves' bands: acting on i (row 0), on j (row 1)
    band += r_s
    near = dist < band
    if members is not None:
        near &= members.take(i) & members.take(j)
    firsts = int(np.count_nonzero(near[0]))
    acting = near.ravel().nonzero()[0]  # halves acting on i, then on j
    bins = me.take(acting)  # the robot acted on, plus n for the halves acting on j
    bins[firsts:] += n
    band = band.ravel().take(acting)
    acting[firsts:] -= i.size  # the pairs
    push = diff.take(acting, axis=1)
    np.negative(push[:, firsts:], out=push[:, firsts:])  # acting on j: p_j - p_i
    return bins, push, dist.take(acting), band


def _summed_pushes(bins: IntArray, push: FloatArray, dist: FloatArray, gain: FloatArray, n: int) -> FloatArray:
    """v_m (2, n) from the acting halves of :func:`_acting_halves` and their phi_m ``gain``: every robot sums the
    halves acting on it as the first robot of their pair and as the second apart, then adds the two sums (the order
    of the sums in docs/'s runs). ``push`` and ``dist`` are overwritten."""
    push /= np.maximum(dist, 1e-12, out=dist)
    push *= gain
    # bins of x: [robot, robot + n] for the halves acting on the pair's first, second robot; y's bins 2n further
    sums = np.bincount(np.concatenate([bins, bins + 2 * n]), weights=push.ravel(), minlength=4 * n)
    sums = sums.reshape(2, 2, n)
    return cast(FloatArray, sums[:, 0] + sums[:, 1])  # weighted: floats


def avoidance_velocity(
    positions: FloatArray,
    r_a: FloatArray,
    params: StepParams,
    members: NDArray[np.bool_] | None = None,
    others: FloatArray | None = None,
) -> FloatArray:
    """v_m of every robot, (2, N): the sum over neighbours closer than r_s + r_a,i of phi_m times the unit p_ij.

    ``members`` (N,) restricts the pairs to robots of the swarm (parked robots have left it); None: all.
    ``others`` (2, N): where each robot believes the others are (their last message, when messages drop); robot i
    still knows its own position. None: everyone sees everyone where they are.
    """
    if others is not None:
        return _avoidance_of_what_is_heard(positions, others, r_a, params, members)
    bins, push, dist, band = _acting_halves(positions, r_a, params, members)
    gain = interaction_gains(dist, band, _NONE, _NONE, params)[0]
    return _summed_pushes(bins, push, dist, gain, positions.shape[1])


def _avoidance_of_what_is_heard(
    positions: FloatArray, others: FloatArray, r_a: FloatArray, params: StepParams, members: NDArray[np.bool_] | None
) -> FloatArray:
    """v_m with robot i at p_i and robot j at q_j as i last heard it: all ordered pairs, dense (the fault study's
    swarm sizes); with q = p it equals the pairwise form."""
    r_s = params.r_s_m
    diff = positions[:, :, None] - others[:, None, :]  # (2, N, N): p_i - q_j
    dist = np.hypot(diff[0], diff[1])
    np.fill_diagonal(dist, np.inf)
    if members is not None:
        dist[~members, :] = np.inf
        dist[:, ~members] = np.inf
    radius = np.broadcast_to(r_a[:, None], dist.shape)
    near = dist < r_s + radius
    gain = np.zeros_like(dist)
    gain[near] = interaction_gains(dist[near], r_s + radius[near], _NONE, _NONE, params)[0]
    weight = np.where(near, gain / np.where(near, dist, 1.0), 0.0)
    return np.einsum('ij,kij->ki', weight, diff)


@dataclass(frozen=True)
class Command:
    """The controller's command and its parts, (2, N) each."""

    velocity: FloatArray
    forward: FloatArray
    avoidance: FloatArray
    tube_keeping: FloatArray


def velocity_command(
    positions: FloatArray,
    r_a: FloatArray,
    forward_speed_mps: FloatArray,
    projection: Any,
    params: StepParams,
    members: NDArray[np.bool_] | None = None,
    others: FloatArray | None = None,
) -> Command:
    """The command v_c of every robot (eq. s1) at (2, N) positions with radii r_a (N,) and forward speeds (N,).

    ``members``, ``others``: the robots that avoid each other, and where they are heard (:func:`avoidance_velocity`).
    The tube keeping v_xy pushes each robot towards the centre line along the normal with phi_t(d_i).
    """
    forward = forward_speed_mps * projection.tangent
    clearance = projection.clearance_m
    if others is None:
        bins, push, dist, band = _acting_halves(positions, r_a, params, members)
        pair_gain, wall_gain = interaction_gains(dist, band, clearance, r_a, params)
        avoidance = _summed_pushes(bins, push, dist, pair_gain, positions.shape[1])
    else:
        avoidance = _avoidance_of_what_is_heard(positions, others, r_a, params, members)
        wall_gain = interaction_gains(_NONE, _NONE, clearance, r_a, params)[1]
    keeping = -wall_gain * np.sign(projection.y_m) * projection.normal
    if params.saturation == 'forward':  # |v_c| >= t_c . v_c >= v* - (v* - v_min) = v_min, then capped at v_max
        room = np.maximum(0.0, forward_speed_mps - params.v_min_mps)
        velocity = cap_norm(forward + cap_norm(avoidance + keeping, room), params.v_max_mps)
    else:
        velocity = saturate(forward + avoidance + keeping, params.v_min_mps, params.v_max_mps, projection.tangent)
    return Command(velocity, forward, avoidance, keeping)


def avoidance_radius_rate(rho_measured: float, rho_planned: ArrayLike, params: StepParams) -> FloatArray:
    """(a3): r_a,i' = k_ra max(0, rho_r - rho*(l_i)), m/s, (N,)."""
    return params.k_ra_m3ps * np.maximum(0.0, rho_measured - np.asarray(rho_planned, dtype=float))


def feedforward_radius(rho_planned: ArrayLike, params: StepParams) -> FloatArray:
    """1/sqrt(rho*) - r_s: the avoidance radius whose lattice (spacing r_s + r_a) has density rho*, (N,)."""
    return 1.0 / np.sqrt(np.asarray(rho_planned, dtype=float)) - params.r_s_m


def next_radius(
    r_a: FloatArray, rho_measured: float, rho_planned: FloatArray, params: StepParams, dt_s: float
) -> FloatArray:
    """r_a after one period of (a3), capped at r_a_max, floored by the feed-forward when it is on."""
    r_a = np.minimum(params.r_a_max_m, r_a + dt_s * avoidance_radius_rate(rho_measured, rho_planned, params))
    if params.feedforward:
        r_a = np.maximum(r_a, np.minimum(params.r_a_max_m, feedforward_radius(rho_planned, params)))
    return r_a


# ---------------------------------------------------------------------- exit and parking


def parking_slots(end_m: ArrayLike, tangent: ArrayLike, n_robots: int, spacing_m: float = 0.25) -> FloatArray:
    """Slots (2, N) beyond the exit ``end_m`` (2,), in lanes ``spacing_m`` apart, filled farthest first."""
    end, tangent = np.asarray(end_m, dtype=float), np.asarray(tangent, dtype=float)
    normal = np.array([-tangent[1], tangent[0]])
    lanes = max(1, min(n_robots, 5))
    slots = []
    for k in range(n_robots):
        depth, lane = divmod(k, lanes)
        slots.append(end + (0.45 - spacing_m * depth) * tangent + (lane - 0.5 * (lanes - 1)) * spacing_m * normal)
    return np.array(slots).T.reshape(2, n_robots)


@dataclass(frozen=True)
class StepResult:
    """One control period: the command, what it was computed from, and the swarm's state.

    ``velocity`` is the single-integrator command (2, N) (parked robots: towards their slot); ``command`` its
    parts; ``r_a_m`` the radii the command used (the step then advanced them by (a3)); ``parked`` the robots that
    have left the tube and drive to a slot; ``done`` when every robot has exited (no slots) or parked.
    """

    velocity: FloatArray
    command: Command
    projection: Any
    forward_speed_mps: FloatArray
    density_per_m2: float
    r_a_m: FloatArray
    parked: NDArray[np.bool_]
    done: bool


class SwarmStep:
    """The swarm controller with its state (avoidance radii, parking assignment), one call per control period.

    Parameters
    ----------
    tube
        Anything with ``project(points) -> Projection``, ``project_near(points, near: Projection) -> Projection``,
        ``area(l)`` and ``length_m``: the exact
        :class:`~vtube_planning.geometry.tube.VirtualTube` or the testbed's
        :class:`~vtube_planning.geometry.projection.SampledTube`.
    params
        The step's numbers.
    n_robots
        Swarm size.
    plan
        The plan to track (forward speed v*(l_i), and r_a by (a3)); None flies *without planning*: constant
        forward speed, constant r_a.
    constant_speed_mps
        The forward speed without a plan.
    parking_slots
        Slots (2, N) beyond the exit for robots that leave the tube; None lets them fly on.
    warm_projection
        Project the robots starting from their previous projection (``tube.project_near``: its arc lengths and the
        frame there; the same arc lengths to about 1e-12 m, certified or else searched globally) instead of searching the whole tube each period
        (``tube.project``). Only when the step projects, i.e. is not given the projection.
    """

    def __init__(
        self,
        tube: Any,
        params: StepParams,
        n_robots: int,
        *,
        plan: PlanProfile | None = None,
        constant_speed_mps: float | None = None,
        parking_slots: FloatArray | None = None,
        warm_projection: bool = True,
    ) -> None:
        if plan is None and constant_speed_mps is None:
            msg = 'a swarm step without a plan needs constant_speed_mps, the forward speed to fly.'
            raise ValueError(msg)
        self.tube = tube
        self.params = params
        self.plan = plan
        self.constant_speed_mps = float(constant_speed_mps) if constant_speed_mps is not None else math.nan
        self.slots = parking_slots
        self.r_a = np.full(n_robots, float(params.r_a_m))
        self.slot_of = np.full(n_robots, -1)
        self.warm_projection = warm_projection
        self._last: Any = None  # the last period's projection, where the warm start begins

    def __call__(
        self, points: FloatArray, dt_s: float, projection: Any = None, others: FloatArray | None = None
    ) -> StepResult:
        """The commands for robots at (2, N) ``points``; advances r_a and the parking assignment by ``dt_s``.

        ``others`` (2, N): where the robots hear each other (their last messages); None: at ``points``.
        """
        p = self.params
        points = np.asarray(points, dtype=float)
        if points.shape != (2, self.r_a.size):
            msg = f'points must have shape (2, {self.r_a.size}), one robot per column; got {points.shape}.'
            raise ValueError(msg)
        if np.count_nonzero(np.isfinite(points)) < points.size:  # a count: the cheapest test of a small array
            msg = f'points of robots {np.flatnonzero(~np.isfinite(points).all(axis=0)).tolist()} are not finite.'
            raise ValueError(msg)
        if projection is None:
            if self.warm_projection and self._last is not None:
                projection = self.tube.project_near(points, self._last)
            else:
                projection = self.tube.project(points)
        self._last = projection
        l_m = projection.l_m
        exited = l_m > self.tube.length_m  # past the exit: the swarm's passage is over for this robot
        if self.slots is not None:  # robots past the exit take the next free slot and leave the swarm
            for k in np.flatnonzero(exited & (self.slot_of < 0)):
                self.slot_of[k] = int((self.slot_of >= 0).sum())
        parked = self.slot_of >= 0
        members = ~parked if np.count_nonzero(parked) else None  # None: every robot flies the tube
        swarm_l, radii = (l_m[members], self.r_a[members]) if members is not None and members.any() else (l_m, self.r_a)
        density = swarm_density(self.tube, swarm_l, p.r_a_m if p.density_padding == 'initial' else float(radii.mean()))
        l_plan = np.full(l_m.size, swarm_l.mean()) if p.plan_at == 'center' else l_m
        if self.plan is not None:
            forward_speed = self.plan.speed(l_plan)
        else:
            forward_speed = np.full(l_m.size, self.constant_speed_mps)
        r_a = self.r_a
        command = velocity_command(points, r_a, forward_speed, projection, p, members, others)
        velocity = command.velocity
        if self.slots is None:
            done = np.count_nonzero(exited) == exited.size
        else:
            velocity, done = self._park(self.slots, points, parked, velocity)
        if self.plan is not None:
            self.r_a = next_radius(r_a, density, self.plan.density(l_plan), p, dt_s)
        return StepResult(velocity, command, projection, forward_speed, density, r_a, parked, done)

    def _park(
        self, slots: FloatArray, points: FloatArray, parked: NDArray[np.bool_], velocity: FloatArray
    ) -> tuple[FloatArray, bool]:
        """Parked robots drive to their slots at up to v_max; done when every robot is in its slot."""
        to_slot = slots[:, self.slot_of[parked]] - points[:, parked]
        reach = np.maximum(np.hypot(to_slot[0], to_slot[1]), 1e-9)
        velocity = velocity.copy()
        velocity[:, parked] = to_slot * np.minimum(1.0, self.params.v_max_mps / reach)
        done = bool(parked.all()) and bool(np.all(np.hypot(*(slots[:, self.slot_of] - points)) < PARKED_WITHIN_M))
        return velocity, done
