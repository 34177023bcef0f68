"""Classic graphs."""

from __future__ import annotations

import numpy as np

import robotarium_exp.rps_classic.utilities.graph as classic_graph


def test_graph_names_and_topological_neighbours() -> None:
    lap = classic_graph.cycle_GL(5)
    np.testing.assert_array_equal(lap.sum(axis=1), 0)
    assert lap[0, 4] == lap[4, 0] == lap[2, 3] == -1 and np.all(np.diag(lap) == 2)
    np.testing.assert_array_equal(classic_graph.topological_neighbors(lap, 0), [1, 4])
    assert lap[0, 0] == 0  # classic edits the caller's Laplacian as it reads the row
