"""``rps.utilities.graph``: graph Laplacians and neighbour queries for the consensus and formation examples.

A Laplacian L of an undirected graph on n nodes has the degree of node i at L[i, i] and -1 at L[i, j] for every
edge {i, j}. The random graphs draw from numpy's global generator (``np.random``), as the testbed's ``rps`` does,
so a script's ``np.random.seed`` makes them reproducible. Misuse raises
``AssertionError`` with the message ``rps`` gives (`robotarium_exp.rps.errors.require`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.rps.errors import require

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]


def _laplacian(n: int, edges: IntArray) -> FloatArray:
    """The Laplacian of the graph on n nodes with the given (k, 2) undirected edges."""
    lap = np.zeros((n, n))
    i, j = edges[:, 0], edges[:, 1]
    lap[i, j] = lap[j, i] = -1.0
    np.fill_diagonal(lap, -lap.sum(axis=1))
    return lap


def completeGL(n: int) -> FloatArray:
    """Every node joined to every other: degree n - 1."""
    require(isinstance(n, int) and n > 0, 'n must be a positive integer.')
    return n * np.eye(n) - np.ones((n, n))


def cycleGL(n: int) -> FloatArray:
    """A ring 0 - 1 - ... - (n-1) - 0: degree 2."""
    require(isinstance(n, int) and n >= 3, 'n must be an integer >= 3.')
    k = np.arange(n)
    return _laplacian(n, np.column_stack([k, (k + 1) % n]))


def lineGL(n: int) -> FloatArray:
    """A path 0 - 1 - ... - (n-1): degree 2 inside, 1 at both ends."""
    require(isinstance(n, int) and n >= 2, 'n must be an integer >= 2.')
    k = np.arange(n - 1)
    return _laplacian(n, np.column_stack([k, k + 1]))


def _add_random_edges(lap: FloatArray, candidates: IntArray, count: int) -> FloatArray:
    """Add ``count`` of the (k, 2) candidate pairs, chosen by shuffling them with ``np.random``."""
    count = min(count, len(candidates))
    if count > 0:
        np.random.shuffle(candidates)
        for i, j in candidates[:count]:
            lap[i, j] = lap[j, i] = -1.0
            lap[i, i] += 1.0
            lap[j, j] += 1.0
    return lap


def random_connectedGL(v: int, e: int) -> FloatArray:
    """A random spanning tree on v nodes (node i joins a random earlier node) plus up to e random extra edges."""
    require(isinstance(v, int) and v > 0, 'v must be a positive integer.')
    require(isinstance(e, int) and e >= 0, 'e must be a non-negative integer.')
    lap = np.zeros((v, v))
    for i in range(1, v):
        j = np.random.randint(0, i)
        lap[i, j] = lap[j, i] = -1.0
        lap[i, i] += 1.0
        lap[j, j] += 1.0
    return _add_random_edges(lap, np.argwhere(np.triu(lap == 0, 1)), e)


def randomGL(v: int, e: int) -> FloatArray:
    """Up to e edges drawn at random among all pairs of v nodes (possibly disconnected)."""
    require(isinstance(v, int) and v > 0, 'v must be a positive integer.')
    require(isinstance(e, int) and e >= 0, 'e must be a non-negative integer.')
    return _add_random_edges(np.zeros((v, v)), np.argwhere(np.triu(np.ones((v, v)), 1)), e)


def delta_disk_neighbors(poses: FloatArray, agent: int, delta: float) -> IntArray:
    """The agents other than ``agent`` whose positions (first two rows of ``poses``) lie within ``delta``."""
    n = poses.shape[1]
    require(0 <= agent < n, f'agent ({agent}) must be between 0 and {n - 1}.')
    others = np.concatenate((np.arange(agent), np.arange(agent + 1, n)))
    if others.size == 0:
        return np.array([], dtype=int)
    distance = np.linalg.norm(poses[:2, others] - poses[:2, agent : agent + 1], axis=0)
    near: IntArray = others[distance <= delta]
    return near


def topological_neighbors(L: FloatArray, agent: int) -> IntArray:
    """The agent's neighbours in the graph of Laplacian L (nonzero off-diagonal entries of its row)."""
    n = L.shape[0]
    require(0 <= agent < n, f'agent ({agent}) must be between 0 and {n - 1}.')
    row = np.array(L[agent, :], dtype=float, copy=True)
    row[agent] = 0.0
    return np.flatnonzero(row != 0)
