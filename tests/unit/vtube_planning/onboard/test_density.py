"""The swarm's measured density: the padded area and N / S by hand."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.onboard.density import swarm_area, swarm_density


def step_tube() -> VirtualTube:
    """Straight, half-width 2 m for 10 m, then 1 m (smooth over 1 m) for the remaining 19 m."""
    width = WidthProfile(
        2.0, (WidthPart('constant', 10.0), WidthPart('smooth', 1.0, to_m=1.0), WidthPart('constant', 19.0))
    )
    return VirtualTube(ArcPath((ArcPiece(30.0),)), width)


def test_line_abreast_swarm_has_the_padded_area() -> None:
    tube = step_tube()
    points = np.vstack([np.full(4, 3.0), np.linspace(-1.5, 1.5, 4)])  # four robots side by side at l = 3
    pad = 0.8
    assert swarm_density(tube, tube.project(points).l_m, pad) == pytest.approx(4 / (2 * 2.0 * 2 * pad))
    assert swarm_area(tube, 2.0, 5.0, 0.0)[0] == pytest.approx(12.0)


def test_measured_density_is_global_n_over_s_and_needs_robots() -> None:
    tube = step_tube()
    points = np.array([[1.0, 4.0, 12.0], [0.0, 1.0, -0.5]])
    area = (
        2 * 2.0 * (10.0 - 0.5) + tube.width.area(np.array([11.0]))[0] - tube.width.area(np.array([10.0]))[0] + 2.0 * 1.5
    )
    assert swarm_density(tube, tube.project(points).l_m, 0.5) == pytest.approx(3 / area)
    with pytest.raises(ValueError, match='at least one robot'):
        swarm_density(tube, np.zeros(0), 0.5)
