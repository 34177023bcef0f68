"""The k nearest points against scipy's k-d tree (the oracle): the same points for every query, over random sets
spread, clustered, thin, on a curve and on a line, queried at the points themselves and far outside them."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from vtube_planning.swarm.nearest import cells, nearest, nearest_in


def _points(kind: str, n: int, rng: np.random.Generator) -> np.ndarray:
    if kind == 'spread':
        return rng.uniform(0.0, rng.uniform(0.1, 50.0), (2, n))
    if kind == 'thin':
        return np.vstack([rng.uniform(0.0, 200.0, n), rng.uniform(0.0, 2.0, n)])
    if kind == 'clusters':
        return np.concatenate([rng.normal(0.0, 1.0, (2, n // 2)), rng.normal(30.0, 0.1, (2, n - n // 2))], axis=1)
    if kind == 'curve':
        t = np.sort(rng.uniform(0.0, 20.0, n))
        return np.vstack([t, np.sin(t)])
    return np.vstack([rng.uniform(0.0, 20.0, n), np.zeros(n)])  # on a line: a straight tube's centre


@pytest.mark.parametrize('kind', ['spread', 'thin', 'clusters', 'curve', 'line'])
def test_the_nearest_points_are_the_k_d_trees(kind: str) -> None:
    rng = np.random.default_rng(len(kind))
    for trial in range(40):
        n = int(rng.integers(2, 300))
        k = int(rng.integers(1, min(n, 25) + 1))
        points = _points(kind, n, rng)
        queries = points if trial % 2 == 0 else rng.uniform(-60.0, 260.0, (2, 40))  # far outside the grid too
        x, y = points
        expected = cKDTree(points.T).query(queries.T, k=k)[1].reshape(queries.shape[1], k)
        for found in (nearest(*queries, x, y, k), nearest_in(cells(x, y, 20.0), *queries, x, y, k)):
            assert [set(row) for row in found] == [set(row) for row in expected]
            distance = np.hypot(*(queries[:, :, None] - points[:, found]))
            assert (np.diff(distance, axis=1) >= 0.0).all()  # nearest first


def test_a_point_finds_itself_first() -> None:
    x, y = np.random.default_rng(3).uniform(0.0, 10.0, (2, 200))
    assert (nearest(x, y, x, y, 5)[:, 0] == np.arange(200)).all()
