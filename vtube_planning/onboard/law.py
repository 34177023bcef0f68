"""The law: the command v_c of every robot, eq. (s1) of ``docs/theory.md`` §2.8.

Every robot i at p_i, projected onto the tube (arc length l_i, tangent t_c, left normal n, offset y_i), commands::

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
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np
from numpy.typing import NDArray

from vtube_planning.onboard.neighbours import EMPTY, acting_halves
from vtube_planning.onboard.params import StepParams
from vtube_planning.onboard.projection import Projection
from vtube_planning.onboard.scalar import barrier_gain, cap_norm, saturate, sigma

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]


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


def _summed_pushes(bins: IntArray, push: FloatArray, dist: FloatArray, gain: FloatArray, n: int) -> FloatArray:
    """v_m (2, n) from the acting halves of :func:`acting_halves` and their phi_m ``gain``: every robot sums the
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
    bins, push, dist, band = acting_halves(positions, r_a, params, members)
    gain = interaction_gains(dist, band, EMPTY, EMPTY, params)[0]
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
    gain[near] = interaction_gains(dist[near], r_s + radius[near], EMPTY, EMPTY, params)[0]
    weight = np.where(near, gain / np.where(near, dist, 1.0), 0.0)
    summed: FloatArray = np.einsum('ij,kij->ki', weight, diff)
    return summed


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
    projection: Projection,
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
        bins, push, dist, band = acting_halves(positions, r_a, params, members)
        pair_gain, wall_gain = interaction_gains(dist, band, clearance, r_a, params)
        avoidance = _summed_pushes(bins, push, dist, pair_gain, positions.shape[1])
    else:
        avoidance = _avoidance_of_what_is_heard(positions, others, r_a, params, members)
        wall_gain = interaction_gains(EMPTY, EMPTY, clearance, r_a, params)[1]
    keeping = -wall_gain * np.sign(projection.y_m) * projection.normal
    if params.saturation == 'forward':  # |v_c| >= t_c . v_c >= v* - (v* - v_min) = v_min, then capped at v_max
        room = np.maximum(0.0, forward_speed_mps - params.v_min_mps)
        velocity = cap_norm(forward + cap_norm(avoidance + keeping, room), params.v_max_mps)
    else:
        velocity = saturate(forward + avoidance + keeping, params.v_min_mps, params.v_max_mps, projection.tangent)
    return Command(velocity, forward, avoidance, keeping)
