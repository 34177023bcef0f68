"""Who pushes whom: the pairs of robots within reach (all pairs of a small swarm, a k-d tree's above
:data:`~vtube_planning.onboard.params.KDTREE_ABOVE` robots) and the halves of them that act."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from vtube_planning.onboard.params import StepParams

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]

EMPTY = np.empty(0)
"""No pairs, or no walls (read-only)."""
EMPTY.flags.writeable = False


def neighbour_pairs(positions: FloatArray, radius: float) -> tuple[IntArray, IntArray]:
    """Pairs (i, j), i < j, of columns of (2, N) positions at most ``radius`` apart, found with a k-d tree
    (O(N log N) time, memory of the order of the pairs found)."""
    # unbalanced and uncompacted: it builds faster and finds the same pairs (robots are spread evenly)
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


def acting_halves(
    positions: FloatArray, r_a: FloatArray, params: StepParams, members: NDArray[np.bool_] | None
) -> tuple[IntArray, FloatArray, FloatArray, FloatArray]:
    """The halves of pairs that push (the robot pushed within r_s + r_a of the other): their bins in the law's sums
    (:mod:`~vtube_planning.onboard.law`), p_pushed - p_other (2, M), distances (M,) and the pushed robots' bands
    r_s + r_a (M,).

    Up to ``params.kdtree_above`` robots every pair is tested, above them a k-d tree finds the pairs within
    r_s + max r_a. Each pair (i, j) acts twice, once on i and once on j, each half within its robot's own band;
    beyond it phi_m is exactly 0, so such halves are dropped before phi_m is evaluated.
    """
    n = positions.shape[1]
    r_s = params.r_s_m
    if n < 2:  # fresh arrays: the caller divides the pushes by the distances in place
        return np.empty(0, dtype=np.intp), np.empty((2, 0)), np.empty(0), np.empty(0)
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
