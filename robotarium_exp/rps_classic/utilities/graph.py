"""Classic ``rps.utilities.graph``: Laplacians and neighbour queries, classic names.

The random graphs, ``lineGL``, ``completeGL`` and ``delta_disk_neighbors`` are V2's (the same draws from
``np.random`` and the same results). Classic's own: the name ``cycle_GL`` (V2 ``cycleGL``), accepted for any
positive N, and ``topological_neighbors``, which zeroes the agent's diagonal entry in the caller's Laplacian
as it reads the row (classic edits the row in place).
"""

from __future__ import annotations

import numpy as np

from robotarium_exp.rps.errors import RobotariumError
from robotarium_exp.rps.utilities.graph import (
    FloatArray,
    IntArray,
    completeGL,
    delta_disk_neighbors,
    lineGL,
    random_connectedGL,
    randomGL,
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


def cycle_GL(N: int) -> FloatArray:
    """The ring 0 - 1 - ... - (N-1) - 0: 2 on the diagonal, -1 between ring neighbours (N >= 3 for a true cycle;
    smaller N give classic's matrices)."""
    if not isinstance(N, int) or N <= 0:
        msg = f'In the cycle_GL function, number of nodes (N) must be a positive integer. Recieved {N!r}.'
        raise RobotariumError(msg)
    lap = 2 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1)
    lap[N - 1, 0] = lap[0, N - 1] = -1
    return lap


def topological_neighbors(L: FloatArray, agent: int) -> IntArray:
    """The agent's neighbours: the nonzero off-diagonal entries of its row. Sets ``L[agent, agent]`` to 0, as classic."""
    if not isinstance(L, np.ndarray) or not isinstance(agent, int) or not 0 <= agent < L.shape[0]:
        msg = f'In the topological_neighbors function, the agent number must be a row of L. Recieved {agent!r}.'
        raise RobotariumError(msg)
    L[agent, agent] = 0
    return np.flatnonzero(L[agent, :] != 0)
