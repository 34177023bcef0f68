"""StepTube: the exact tube and the samples a submission carries both give what the swarm step calls."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.onboard.tube import StepTube

EXACT = VirtualTube(ArcPath((ArcPiece(5.0),)), WidthProfile(1.0, (WidthPart('constant', 5.0),)))


@pytest.mark.parametrize('tube', [EXACT, EXACT.sampled(0.5)], ids=['exact', 'sampled'])
def test_both_tubes_have_the_members_of_a_step_tube(tube: StepTube) -> None:
    """A straight tube of length 5 and half-width 1 along x: l = x, y = y, A(l) = 2 l (also beyond the ends)."""
    for member in ('length_m', 'project', 'project_near', 'area'):
        assert hasattr(tube, member), member
    points = np.array([[2.0, -1.0, 6.0], [0.5, 0.2, -0.3]])
    p = tube.project(points)
    assert tube.length_m == pytest.approx(5.0)
    np.testing.assert_allclose(p.l_m, points[0], atol=1e-12)
    np.testing.assert_allclose(p.y_m, points[1], atol=1e-12)
    np.testing.assert_allclose(tube.project_near(points, p).l_m, points[0], atol=1e-12)
    np.testing.assert_allclose(np.asarray(tube.area(np.array([-1.0, 2.0, 6.0]))), [-2.0, 4.0, 12.0], atol=1e-12)
