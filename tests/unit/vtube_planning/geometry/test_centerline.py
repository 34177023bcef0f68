"""Centre curves: arcs and splines against analytic curvature, finite differences and quadrature."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.interpolate import CubicSpline

from tests.support.tubes import WAYPOINTS, arc_tube, spline_tube
from vtube_planning.geometry.centerline import ArcPath, ArcPiece, SplineCurve
from vtube_planning.geometry.scene import load_scene

# ---------------------------------------------------------------------- analytic curves


@pytest.mark.parametrize('left', [True, False])
def test_circle_arc_curvature_is_one_over_radius(left: bool) -> None:
    radius = 7.0
    tube = arc_tube(radius, 150.0, left)
    l = np.linspace(0.0, tube.length_m, 101)
    sign = 1.0 if left else -1.0
    np.testing.assert_allclose(tube.curvature(l), sign / radius, rtol=1e-14)
    np.testing.assert_allclose(tube.curvature_radius(l), radius, rtol=1e-14)
    center_of_circle = np.array([0.0, sign * radius])  # start at the origin heading +x
    np.testing.assert_allclose(np.linalg.norm(tube.center_at(l) - center_of_circle, axis=1), radius, atol=1e-12)
    # the tangent is perpendicular to the radius, the left normal points to the centre for a left turn
    to_centre = center_of_circle - tube.center_at(l)
    np.testing.assert_allclose(np.einsum('ij,ij->i', tube.tangent(l), to_centre), 0.0, atol=1e-12)
    np.testing.assert_allclose(np.einsum('ij,ij->i', tube.normal(l), to_centre) / radius, sign, atol=1e-12)


def test_analytic_path_pieces_join_with_continuous_tangent() -> None:
    path = ArcPath((ArcPiece(3.0), ArcPiece(4.0, radius_m=2.0), ArcPiece(2.0), ArcPiece(5.0, 3.0, left=False)))
    for b in path.breakpoints[1:-1]:
        before, after = path.frame(np.array([b - 1e-9, b]))[:2]
        np.testing.assert_allclose(before[0], before[1], atol=1e-8)
        np.testing.assert_allclose(after[0], after[1], atol=1e-8)
    # the heading after all pieces is the sum of the turns
    end_tangent = path.frame(np.array([path.length_m]))[1][0]
    heading = 4.0 / 2.0 - 5.0 / 3.0
    np.testing.assert_allclose(end_tangent, [math.cos(heading), math.sin(heading)], atol=1e-14)


@pytest.mark.parametrize('make', [arc_tube, spline_tube, lambda: load_scene('B').tube], ids=['arc', 'spline', 'B'])
def test_tangent_and_curvature_match_finite_differences(make) -> None:
    tube = make()
    h = 1e-5
    l = np.linspace(2 * h, tube.length_m - 2 * h, 301)
    l = l[np.min(np.abs(l[:, None] - tube.center.breakpoints[None, :]), axis=1) > 2 * h]  # curvature jumps at joints
    d_gamma = (tube.center_at(l + h) - tube.center_at(l - h)) / (2 * h)
    np.testing.assert_allclose(d_gamma, tube.tangent(l), atol=1e-8)  # also |gamma'| = 1: true arc length
    d_tangent = (tube.tangent(l + h) - tube.tangent(l - h)) / (2 * h)
    np.testing.assert_allclose(d_tangent, tube.curvature(l)[:, None] * tube.normal(l), atol=1e-6)


# ---------------------------------------------------------------------- spline curves


def test_spline_arc_length_matches_dense_numerical_integral() -> None:
    pts = np.array(WAYPOINTS)
    u = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    spline = CubicSpline(u, pts, bc_type='natural')  # the documented construction, rebuilt independently

    def speed(s: float) -> float:
        return float(np.hypot(*spline(s, 1)))

    length = sum(quad(speed, a, b, epsabs=1e-13, epsrel=1e-13, limit=200)[0] for a, b in itertools.pairwise(u))
    tube = spline_tube()
    assert abs(tube.length_m - length) <= 1e-6 * length
    # and the curve passes through every waypoint, at increasing arc length
    np.testing.assert_allclose(tube.center_at(tube.center.breakpoints), pts, atol=1e-9)
    assert np.all(np.diff(tube.center.breakpoints) > 0)


def test_spline_through_circle_points_has_curvature_close_to_one_over_radius() -> None:
    radius = 10.0
    phi = np.linspace(0.0, math.pi / 2, 40)
    curve = SplineCurve(tuple(zip(radius * np.sin(phi), radius * (1 - np.cos(phi)), strict=True)))
    l = np.linspace(0.2 * curve.length_m, 0.8 * curve.length_m, 50)  # away from the natural (kappa = 0) ends
    np.testing.assert_allclose(curve.frame(l)[2], 1.0 / radius, rtol=1e-3)
    assert abs(curve.length_m - radius * math.pi / 2) < 1e-4
