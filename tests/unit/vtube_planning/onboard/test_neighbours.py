"""Neighbour pairs: the k-d tree and all pairs give the same pairs and the same law."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vtube_planning.onboard.law import avoidance_velocity
from vtube_planning.onboard.neighbours import neighbour_pairs
from vtube_planning.onboard.params import KDTREE_ABOVE
from vtube_planning.params import ControlParams, SwarmParams

SWARM = SwarmParams()  # r_s = 0.4, r_a = 0.8, v in [2, 5]


@pytest.mark.parametrize('n', [KDTREE_ABOVE // 2, 5 * KDTREE_ABOVE])
def test_kd_tree_and_all_pairs_give_the_same_law(n: int) -> None:
    """Below and above the crossover, each path forced: the same pairs and the same avoidance term."""
    rng = np.random.default_rng(n)
    side = np.sqrt(n)  # about one robot per m^2, so robots have neighbours within and beyond their bands
    positions = np.vstack([rng.uniform(0, 2 * side, n), rng.uniform(0, 0.5 * side, n)])
    r_a = rng.uniform(0.8, 1.6, n)
    members = rng.random(n) > 0.1
    for law in ('barrier', 'practical'):
        dense = avoidance_velocity(positions, r_a, ControlParams(law=law, kdtree_above=n).step_params(SWARM), members)
        tree = avoidance_velocity(positions, r_a, ControlParams(law=law, kdtree_above=0).step_params(SWARM), members)
        assert np.count_nonzero(np.hypot(*dense)) > n // 4  # the test sees pushes
        np.testing.assert_allclose(tree, dense, rtol=1e-12, atol=1e-12 * np.abs(dense).max())
    i, j = neighbour_pairs(positions, 1.5)
    every = [(a, b, math.dist(positions[:, a], positions[:, b])) for a in range(n) for b in range(a + 1, n)]
    assert sorted(zip(i.tolist(), j.tolist())) == [(a, b) for a, b, dist in every if dist < 1.5]
