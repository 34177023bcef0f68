"""The virtual tube: projection exact on analytic tubes and the closest point on shipped ones, warm projections,
cumulative area, input contracts."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.spatial import cKDTree

from robotarium_exp.scene import load_scene
from vtube_planning.errors import ShapeError, TubeError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece, SplineCurve
from vtube_planning.geometry.scene import list_scenes
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart

EXACT = 1e-9  # m: the bound for analytic tubes
from tests.support.tubes import arc_tube, constant, spline_tube, straight_tube


def test_straight_tube_projection_is_exact() -> None:
    tube = straight_tube()
    rng = np.random.default_rng(1)
    l_true = rng.uniform(-3.0, 13.0, 500)  # including points before the entrance and past the exit
    y_true = rng.uniform(-3.0, 3.0, 500)
    t = np.array([math.cos(math.radians(30.0)), math.sin(math.radians(30.0))])
    n = np.array([-t[1], t[0]])
    points = (np.array([1.0, -2.0]) + l_true[:, None] * t + y_true[:, None] * n).T
    proj = tube.project(points)
    np.testing.assert_allclose(proj.l_m, l_true, atol=EXACT)
    np.testing.assert_allclose(proj.y_m, y_true, atol=EXACT)
    np.testing.assert_allclose(proj.tangent, np.repeat(t[:, None], 500, axis=1), atol=1e-15)
    expected_inside = (l_true >= 0) & (l_true <= 10) & (np.abs(y_true) <= 1.5)
    np.testing.assert_array_equal(proj.inside, expected_inside)
    np.testing.assert_allclose(proj.clearance_m, 1.5 - np.abs(y_true), atol=EXACT)


@pytest.mark.parametrize('left', [True, False])
def test_circle_arc_projection_is_exact(left: bool) -> None:
    radius = 5.0
    tube = arc_tube(radius, 120.0, left)
    sign = 1.0 if left else -1.0
    rng = np.random.default_rng(2)
    phi = rng.uniform(0.0, math.radians(120.0), 400)
    r = rng.uniform(radius - 2.0, radius + 2.0, 400)
    # polar coordinates about the circle's centre (0, sign R); the curve starts at angle -pi/2 (left turn)
    base = -sign * math.pi / 2 + sign * phi
    points = np.vstack([r * np.cos(base), sign * radius + r * np.sin(base)])
    proj = tube.project(points)
    np.testing.assert_allclose(proj.l_m, radius * phi, atol=EXACT)
    np.testing.assert_allclose(proj.y_m, sign * (radius - r), atol=EXACT)


def test_spline_projection_recovers_curvilinear_coordinates() -> None:
    tube = spline_tube()
    rng = np.random.default_rng(3)
    l_true = rng.uniform(0.0, tube.length_m, 2000)
    y_true = rng.uniform(-1.0, 1.0, 2000) * tube.half_width(l_true)
    points = (tube.center_at(l_true) + y_true[:, None] * tube.normal(l_true)).T
    proj = tube.project(points)
    np.testing.assert_allclose(proj.l_m, l_true, atol=1e-9)
    np.testing.assert_allclose(proj.y_m, y_true, atol=1e-9)
    assert proj.inside.all()


@pytest.mark.parametrize('name', list_scenes())
def test_projection_of_shipped_scenes_is_the_closest_point(name: str) -> None:
    """Random points in and around every shipped tube: the foot is orthogonal and beats a dense search."""
    tube = load_scene(name).tube
    rng = np.random.default_rng(4)
    l = rng.uniform(0.0, tube.length_m, 300)
    y = rng.uniform(-1.2, 1.2, 300) * tube.half_width(l)
    points = (tube.center_at(l) + y[:, None] * tube.normal(l)).T
    proj = tube.project(points)
    residual = points - proj.foot_m
    np.testing.assert_allclose(np.einsum('ij,ij->j', residual, proj.tangent), 0.0, atol=1e-9)
    dense = tube.center_at(np.linspace(0.0, tube.length_m, 20001))
    brute = cKDTree(dense).query(points.T)[0]  # the nearest of the dense points, exactly
    found = np.linalg.norm(residual, axis=0)
    assert np.all(found <= brute + 1e-12)
    assert np.all(brute - found <= 0.5 * tube.length_m / 20000)  # dense search loses at most half its spacing


def hairpin_tube() -> VirtualTube:
    """Two 10 m legs 3 m apart joined by a half circle: the centre line comes back 3 m from itself."""
    pieces = (ArcPiece(10.0), ArcPiece(math.pi * 1.5, 1.5), ArcPiece(10.0))
    return VirtualTube(ArcPath(pieces), constant(20.0 + math.pi * 1.5, 0.6))


def centre_projection(tube: VirtualTube, l_m: np.ndarray):
    """The projection of the centre-line points at arc lengths ``l_m``: a warm start from exactly those."""
    return tube.project(tube.center_at(l_m).T)


def assert_same_projection(warm, cold) -> None:
    np.testing.assert_allclose(warm.l_m, cold.l_m, rtol=0, atol=EXACT)
    np.testing.assert_allclose(warm.y_m, cold.y_m, rtol=0, atol=EXACT)
    np.testing.assert_allclose(warm.foot_m, cold.foot_m, rtol=0, atol=EXACT)
    np.testing.assert_allclose(warm.tangent, cold.tangent, rtol=0, atol=EXACT)


@pytest.mark.parametrize('name', ['D', 'robotarium_curve', 'robotarium_trapezoid', 'hairpin'])
def test_warm_projection_is_the_cold_one_after_random_motions(name: str) -> None:
    """Points in and around the tube, started from arc lengths moved by centimetres, metres or across the tube."""
    tube = hairpin_tube() if name == 'hairpin' else load_scene(name).tube
    rng = np.random.default_rng(5)
    l = rng.uniform(-0.2 * tube.length_m, 1.2 * tube.length_m, 600)
    y = rng.uniform(-1.5, 1.5, 600) * tube.half_width(l)
    points = (tube.center_at(l) + y[:, None] * tube.normal(l)).T
    cold = tube.project(points)
    for jump_m in (0.01, 0.3, 3.0, tube.length_m):
        start = centre_projection(tube, cold.l_m + rng.normal(0.0, jump_m, l.size))
        assert_same_projection(tube.project_near(points, start), cold)


def test_warm_projection_falls_back_where_the_local_answer_is_the_wrong_leg() -> None:
    """Robots that jump to the other leg of a hairpin: Newton from the old arc length converges on the old leg (a
    stationary point, the wrong answer); the certificate rejects it and the global search finds the right leg."""
    tube = hairpin_tube()
    rng = np.random.default_rng(6)
    l_old = rng.uniform(0.5, 9.5, 300)
    l_new = tube.length_m - l_old + rng.uniform(-0.5, 0.5, 300)  # right across, on the other leg
    points = (tube.center_at(l_new) + rng.uniform(-0.5, 0.5, 300)[:, None] * tube.normal(l_new)).T
    cold = tube.project(points)
    old = centre_projection(tube, l_old)
    local, _, _, _, converged, _ = tube._local_newton(points, old)
    wrong = converged & (np.abs(local - cold.l_m) > 1.0)
    assert wrong.sum() > 100  # the oracle sees the trap
    assert_same_projection(tube.project_near(points, old), cold)
    between = np.vstack([rng.uniform(0.0, 10.0, 300), rng.uniform(1.3, 1.7, 300)])  # near the medial axis
    start = centre_projection(tube, np.clip(between[0], 0.0, 10.0))
    assert_same_projection(tube.project_near(between, start), tube.project(between))


def test_warm_projection_checks_its_start() -> None:
    tube = straight_tube()
    with pytest.raises(ShapeError, match='near must project 3 points'):
        tube.project_near(np.zeros((2, 3)), tube.project(np.zeros((2, 2))))


@pytest.mark.parametrize('name', list_scenes())
def test_cumulative_area_matches_quadrature_and_inverts(name: str) -> None:
    tube = load_scene(name).tube
    breaks = tube.width.breakpoints
    for l_end in np.linspace(0.0, tube.length_m, 7):
        pts = breaks[(breaks > 0) & (breaks < l_end)]
        integral = quad(
            lambda s: 2.0 * tube.half_width(s),
            0.0,
            l_end,
            points=pts if pts.size else None,
            epsabs=1e-12,
            epsrel=1e-12,
            limit=200,
        )[0]
        assert tube.area(l_end) == pytest.approx(integral, rel=1e-10, abs=1e-12)
    l = np.linspace(-2.0, tube.length_m + 2.0, 501)  # the straight extensions keep their end widths
    np.testing.assert_allclose(tube.area_inverse(tube.area(l)), l, atol=1e-9 * tube.length_m)
    assert np.all(np.diff(tube.area(l)) > 0)


def test_width_and_centre_line_must_have_the_same_length() -> None:
    with pytest.raises(TubeError, match=r'cover 9\.000000 m but the centre line is 10\.000000 m'):
        VirtualTube(ArcPath((ArcPiece(10.0),)), constant(9.0))


@pytest.mark.parametrize(
    ('build', 'match'),
    [
        (lambda: WidthPart('wavy', 1.0), 'kind must be one of'),
        (lambda: WidthPart('constant', 0.0), 'length_m must be finite and > 0'),
        (lambda: WidthPart('linear', 2.0, to_m=1.0, corner_m=1.5), r'corner_m .* \[0, 1\]'),
        (lambda: WidthPart('smooth', 2.0), 'needs to_m'),
        (lambda: ArcPiece(1.0, radius_m=-2.0), 'radius_m finite and > 0'),
        (lambda: SplineCurve(((0.0, 0.0), (0.0, 0.0), (1.0, 0.0))), 'waypoints 0 and 1 coincide'),
        (lambda: SplineCurve(((0.0, 0.0),)), r'shape \(M, 2\); got shape \(1, 2\)'),
    ],
)
def test_bad_construction_raises_tube_error(build, match: str) -> None:
    with pytest.raises(TubeError, match=match):
        build()


# ---------------------------------------------------------------------- shape contracts


def test_shape_contract_of_arc_length_functions() -> None:
    tube = spline_tube()
    for fun in (tube.center_at, tube.tangent, tube.normal):
        assert fun(1.0).shape == (2,)
        assert fun(np.array([1.0, 2.0, 3.0])).shape == (3, 2)
        assert fun(np.array([])).shape == (0, 2)
    for scalar_fun in (
        tube.curvature,
        tube.curvature_radius,
        tube.half_width,
        tube.half_width_slope,
        tube.area,
        tube.area_inverse,
    ):
        assert isinstance(scalar_fun(1.0), float)
        assert np.shape(scalar_fun(np.array([1.0, 2.0, 3.0]))) == (3,)
    left, right = tube.boundaries(1.0)
    assert left.shape == right.shape == (2,)
    left, right = tube.boundaries([1.0, 2.0])
    assert left.shape == right.shape == (2, 2)
    np.testing.assert_allclose(np.linalg.norm(left - right, axis=1), 2.0 * tube.half_width(np.array([1.0, 2.0])))


def test_shape_contract_of_projection() -> None:
    tube = straight_tube()
    proj = tube.project(np.zeros((2, 7)))
    assert proj.l_m.shape == proj.y_m.shape == proj.half_width_m.shape == proj.clearance_m.shape == (7,)
    assert proj.foot_m.shape == proj.tangent.shape == proj.normal.shape == (2, 7)
    assert proj.inside.shape == (7,) and proj.inside.dtype == bool
    assert tube.project(np.array([1.0, 2.0])).l_m.shape == (1,)
    assert tube.project(np.zeros((2, 0))).l_m.shape == (0,)


@pytest.mark.parametrize(
    ('points', 'match'),
    [
        (np.zeros((3, 4)), r'shape \(2, N\).*got \(3, 4\)'),
        (np.zeros((4, 2, 1)), r'got \(4, 2, 1\)'),
        (np.array([[0.0, np.nan], [1.0, 1.0]]), r'columns \[1\] contain NaN'),
    ],
)
def test_projection_rejects_bad_points(points: np.ndarray, match: str) -> None:
    with pytest.raises(ShapeError, match=match):
        straight_tube().project(points)


def test_arc_length_functions_reject_bad_input() -> None:
    tube = straight_tube()
    with pytest.raises(ShapeError, match=r'1-D array of shape \(k,\); got shape \(2, 2\)'):
        tube.center_at(np.zeros((2, 2)))
    with pytest.raises(ShapeError, match='must be finite'):
        tube.half_width(np.array([1.0, np.inf]))
    with pytest.raises(ValueError, match='finite'):  # ShapeError is a ValueError
        tube.curvature(float('nan'))


def test_a_projection_carries_the_curvature_at_its_feet() -> None:
    """What a warm start begins with: kappa(l) at the foot, zero on the straight extensions beyond both ends."""
    tube = hairpin_tube()
    rng = np.random.default_rng(7)
    l = rng.uniform(-3.0, tube.length_m + 3.0, 400)
    points = (tube.center_at(l) + rng.uniform(-0.5, 0.5, 400)[:, None] * tube.normal(l)).T
    for projection in (tube.project(points), tube.project_near(points, centre_projection(tube, l + 0.05))):
        inside = (projection.l_m > 0.0) & (projection.l_m < tube.length_m)
        np.testing.assert_array_equal(projection.curvature_per_m[~inside], 0.0)
        np.testing.assert_allclose(projection.curvature_per_m[inside], tube.curvature(projection.l_m[inside]))
    assert np.count_nonzero(tube.project(points).curvature_per_m) > 50  # the oracle sees the arc
