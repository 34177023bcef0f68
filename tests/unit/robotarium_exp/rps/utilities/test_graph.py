"""Graphs of the V2 utilities: Laplacians, degrees, random graphs, neighbours."""

from __future__ import annotations

import numpy as np
import pytest

import robotarium_exp.rps.utilities.graph as v2_graph


def is_laplacian(lap: np.ndarray) -> bool:
    off = lap - np.diag(np.diag(lap))
    return bool(np.allclose(lap, lap.T) and np.allclose(lap.sum(axis=1), 0) and set(np.unique(off)) <= {-1.0, 0.0})


def connected(lap: np.ndarray) -> bool:
    return int(np.sum(np.linalg.eigvalsh(lap) < 1e-9)) == 1  # one zero eigenvalue


def test_named_graphs_have_their_degrees() -> None:
    for n in (3, 4, 7):
        for lap, degrees in (
            (v2_graph.completeGL(n), np.full(n, n - 1)),
            (v2_graph.cycleGL(n), np.full(n, 2)),
            (v2_graph.lineGL(n), np.r_[1, np.full(n - 2, 2), 1]),
        ):
            assert is_laplacian(lap) and connected(lap)
            np.testing.assert_array_equal(np.diag(lap), degrees)
    np.testing.assert_array_equal(v2_graph.topological_neighbors(v2_graph.cycleGL(5), 0), [1, 4])
    np.testing.assert_array_equal(v2_graph.topological_neighbors(v2_graph.lineGL(5), 4), [3])


def test_random_graphs_follow_numpy_seed_and_their_edge_counts() -> None:
    for seed in range(20):
        np.random.seed(seed)
        lap = v2_graph.random_connectedGL(8, 3)
        assert is_laplacian(lap) and connected(lap) and np.trace(lap) / 2 == 7 + 3  # tree plus 3 edges
        np.random.seed(seed)
        np.testing.assert_array_equal(v2_graph.random_connectedGL(8, 3), lap)  # the script's seed holds
        assert np.trace(v2_graph.randomGL(6, 4)) / 2 == 4 and np.trace(v2_graph.randomGL(4, 99)) / 2 == 6  # capped


def test_delta_disk_neighbors_and_misuse() -> None:
    poses = np.array([[0.0, 0.3, 1.0, 0.0], [0.0, 0.0, 0.0, 0.5], [0.0, 1.0, 2.0, 3.0]])
    np.testing.assert_array_equal(v2_graph.delta_disk_neighbors(poses, 0, 0.5), [1, 3])
    with pytest.raises(AssertionError, match=r'agent \(4\) must be between 0 and 3\.') as caught:
        v2_graph.delta_disk_neighbors(poses, 4, 0.5)
    assert caught.type is AssertionError  # V2's own type, not a subclass
    with pytest.raises(AssertionError, match='n must be an integer >= 3.'):
        v2_graph.cycleGL(2)
