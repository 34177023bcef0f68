"""The workspace rectangle: its signed clearance and its checks."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.errors import SceneError
from vtube_planning.geometry.workspace import Workspace


def test_clearance_is_the_distance_to_the_nearest_edge_signed_inside() -> None:
    ws = Workspace(-1.6, 1.6, -1.0, 1.0, margin_m=0.1)
    points = np.array([[0.0, 0.0], [1.5, 0.2], [0.3, -0.9], [1.7, 0.0], [0.0, -1.25]])
    np.testing.assert_allclose(ws.clearance(points), [1.0, 0.1, 0.1, -0.1, -0.25], atol=1e-12)


@pytest.mark.parametrize(
    'bounds',
    [(1.0, -1.0, -1.0, 1.0, 0.0), (-1.0, 1.0, 1.0, 1.0, 0.0), (-1.0, 1.0, -1.0, 1.0, -0.1), (-1.0, np.nan, 0, 1, 0)],
)
def test_an_empty_rectangle_a_negative_margin_or_a_nan_is_refused(bounds) -> None:
    with pytest.raises(SceneError, match='workspace'):
        Workspace(*bounds)
