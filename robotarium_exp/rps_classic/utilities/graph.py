"""Classic ``rps.utilities.graph``: Laplacians and neighbour queries, classic names, checks and edge cases.

``completeGL`` and ``random_connectedGL`` compute what V2's do (the same draws from ``np.random``);
``randomGL`` draws its edges as classic does (a permutation of every candidate pair, even when none is kept).
Classic's own: the name ``cycle_GL`` (V2 ``cycleGL``); any positive number of nodes (``lineGL(1)`` is ``[[1.]]``,
``cycle_GL(1)`` classic's ``[[-1.]]``); ``randomGL`` unchecked, as classic (``e = -1`` keeps all pairs but one);
``topological_neighbors`` zeroes the agent's diagonal entry in the caller's Laplacian as it reads the row (classic
edits the row in place); and classic's checks and messages (`checks`).
"""

from __future__ import annotations

import numpy as np

from robotarium_exp.rps.utilities import graph as v2
from robotarium_exp.rps.utilities.graph import FloatArray, IntArray
from robotarium_exp.rps_classic.utilities.checks import (
    AT_LEAST_ZERO,
    INTEGER,
    NDARRAY,
    NUMBER,
    POSITIVE,
    Check,
    Kind,
    bound,
    enforce,
    typed,
)

__all__ = [
    'completeGL',
    'cycle_GL',
    'delta_disk_neighbors',
    'lineGL',
    'randomGL',
    'random_connectedGL',
    'topological_neighbors',
]

NODES = (typed('N', 'the number of nodes (N)', INTEGER), bound('N', 'number of nodes (N)', POSITIVE))
"""The checks of ``cycle_GL``, ``lineGL`` and ``completeGL``."""

RANDOM_CONNECTED = (
    typed('v', 'the number of verticies (v)', INTEGER),
    typed('e', 'the number of additional edges (e)', INTEGER),
    bound('v', 'number of verticies (v)', POSITIVE),
    bound('e', 'number of additional edges (e)', AT_LEAST_ZERO),
)

AGENT = 'the agent number (agent)'
TOPOLOGICAL = (
    typed('L', 'the graph Laplacian (L)', NDARRAY),
    typed('agent', AGENT, INTEGER),
    bound('agent', AGENT, AT_LEAST_ZERO),
    Check(
        lambda v: v['agent'] <= v['L'].shape[0],
        f'{AGENT} must be within the dimension of the provided Laplacian (L). '
        'Recieved agent number %r and Laplactian size %r by %r.',
        lambda v: (v['agent'], v['L'].shape[0], v['L'].shape[1]),
    ),
)

DELTA_DISK = (
    typed('poses', 'the robot poses (poses)', NDARRAY),
    typed('agent', AGENT, INTEGER),
    typed('delta', AGENT, Kind(NUMBER.types, INTEGER.words), shown='agent'),  # classic's words: of agent
    bound('agent', AGENT, AT_LEAST_ZERO),
    bound('delta', 'the sensing/communication radius (delta)', AT_LEAST_ZERO),
    Check(
        lambda v: v['agent'] <= v['poses'].shape[1],
        f'{AGENT} must be within the dimension of the provided poses. Recieved agent number %r and poses for %r agents.',
        lambda v: (v['agent'], v['poses'].shape[1]),
    ),
)


def _ring(N: int) -> FloatArray:
    """2 on the diagonal, -1 beside it: the path's inner rows and the cycle's, before their ends are set."""
    return 2 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1)


def cycle_GL(N: int) -> FloatArray:
    """The ring 0 - 1 - ... - (N-1) - 0 (N >= 3 for a true cycle; smaller N give classic's matrices)."""
    enforce('In the cycle_GL function', NODES, {'N': N})
    lap = _ring(N)
    lap[N - 1, 0] = lap[0, N - 1] = -1
    return lap


def lineGL(N: int) -> FloatArray:
    """The path 0 - 1 - ... - (N-1): degree 2 inside, 1 at both ends (``[[1.]]`` for one node, as classic)."""
    enforce('In the lineGL function', NODES, {'N': N})
    lap = _ring(N)
    lap[0, 0] = lap[N - 1, N - 1] = 1
    return lap


def completeGL(N: int) -> FloatArray:
    """Every node joined to every other: N I - 1 1^T."""
    enforce('In the completeGL function', NODES, {'N': N})
    return v2.completeGL(N)


def random_connectedGL(v: int, e: int) -> FloatArray:
    """A random spanning tree on v nodes plus up to e random extra edges (V2's draws, classic's checks)."""
    enforce('In the random_connectedGL function', RANDOM_CONNECTED, {'v': v, 'e': e})
    return v2.random_connectedGL(v, e)


def randomGL(v: int, e: int) -> FloatArray:
    """``min(e, pairs)`` edges among the v (v - 1) / 2 pairs, picked by a permutation of all pairs drawn from
    ``np.random``; unchecked, as classic (a negative e drops that many pairs from the end of the permutation)."""
    pairs = np.argwhere(np.tril(np.ones((v, v))) == 0)
    picked = np.random.permutation(len(pairs))[: min(e, len(pairs))]
    lap = np.zeros((v, v))
    for i, j in pairs[picked]:
        lap[i, j] = lap[j, i] = -1.0
        lap[i, i] += 1.0
        lap[j, j] += 1.0
    return lap


def topological_neighbors(L: FloatArray, agent: int) -> IntArray:
    """The agent's neighbours: the nonzero off-diagonal entries of its row. Sets ``L[agent, agent]`` to 0, as classic."""
    enforce('In the topological_neighbors function', TOPOLOGICAL, {'L': L, 'agent': agent})
    L[agent, agent] = 0
    return np.flatnonzero(L[agent, :] != 0)


def delta_disk_neighbors(poses: FloatArray, agent: int, delta: float) -> IntArray:
    """The agents other than ``agent`` within ``delta`` of it (first two rows of ``poses``)."""
    enforce('In the delta_disk_neighbors function', DELTA_DISK, {'poses': poses, 'agent': agent, 'delta': delta})
    robots = np.arange(poses.shape[1])
    near = [bool(np.linalg.norm(poses[:2, k] - poses[:2, agent]) <= delta) for k in robots]
    near[agent] = False
    return robots[near]
