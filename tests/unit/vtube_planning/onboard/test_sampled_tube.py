"""SampledTube: the polyline projection against closed forms and the exact tube it samples."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robotarium_exp.scene import load_scene
from vtube_planning.onboard.sampled_tube import SampledTube


def straight(heading: float = 0.3) -> SampledTube:
    """A straight tube of length 4 from (1, 2) at ``heading``, half-width 1 then 0.5 (linear), in 5 samples."""
    l_m = np.linspace(0.0, 4.0, 5)
    direction = np.array([math.cos(heading), math.sin(heading)])
    xy = np.array([1.0, 2.0])[:, None] + direction[:, None] * l_m
    lam = np.interp(l_m, [0.0, 4.0], [1.0, 0.5])
    area = np.concatenate([[0.0], np.cumsum(np.diff(l_m) * (lam[1:] + lam[:-1]))])  # 2 lambda, trapezoids
    return SampledTube(l_m, xy, lam, area)


def test_a_straight_polyline_projects_points_exactly_also_beyond_its_ends() -> None:
    heading = 0.3
    tube = straight(heading)
    t, n = np.array([math.cos(heading), math.sin(heading)]), np.array([-math.sin(heading), math.cos(heading)])
    l_true, y_true = np.array([-1.0, 0.3, 2.5, 4.0, 5.5]), np.array([0.2, -0.4, 0.5, 0.0, -1.0])
    points = np.array([1.0, 2.0])[:, None] + t[:, None] * l_true + n[:, None] * y_true
    p = tube.project(points)
    np.testing.assert_allclose(p.l_m, l_true, atol=1e-12)
    np.testing.assert_allclose(p.y_m, y_true, atol=1e-12)
    np.testing.assert_allclose(p.foot_m, points - n[:, None] * y_true, atol=1e-12)
    np.testing.assert_allclose(p.tangent, np.tile(t[:, None], 5), atol=1e-12)
    np.testing.assert_allclose(p.normal, np.tile(n[:, None], 5), atol=1e-12)
    np.testing.assert_allclose(p.half_width_m, np.interp(l_true, [0, 4], [1.0, 0.5]))  # ends held
    assert p.length_m == tube.length_m == 4.0 and not p.curvature_per_m.any()
    assert p.inside.tolist() == [False, True, True, True, False]


def test_the_area_is_the_sampled_one_continued_with_the_end_widths() -> None:
    tube = straight()
    np.testing.assert_allclose(tube.area([0.0, 2.0, 4.0]), [0.0, 2 * 2 * 0.875, 2 * 4 * 0.75])
    np.testing.assert_allclose(tube.area([-1.0, 5.0]), [-2.0, 6.0 + 2 * 0.5])


def test_project_near_is_project() -> None:
    tube = straight()
    points = np.array([[1.5, 3.0], [2.5, 2.0]])
    near, cold = tube.project_near(points, tube.project(points + 0.1)), tube.project(points)
    np.testing.assert_array_equal(near.l_m, cold.l_m)
    np.testing.assert_array_equal(near.y_m, cold.y_m)


def test_on_a_corner_the_closer_leg_wins() -> None:
    """An L-shaped polyline (0,0) -> (2,0) -> (2,2): a point at (1.5, 0.2) is on the first leg, (1.8, 1.5) the second."""
    tube = SampledTube([0.0, 2.0, 4.0], [[0.0, 2.0, 2.0], [0.0, 0.0, 2.0]], [0.5] * 3, [0.0, 2.0, 4.0])
    p = tube.project(np.array([[1.5, 1.8], [0.2, 1.5]]))
    np.testing.assert_allclose(p.l_m, [1.5, 3.5])
    np.testing.assert_allclose(p.y_m, [0.2, 0.2])  # left of the first leg, left of the second (-x is its left)


@pytest.mark.parametrize('name', ['robotarium_curve', 'robotarium_trapezoid'])
def test_samples_a_centimetre_apart_agree_with_the_exact_tube_within_the_chord_bound(name: str) -> None:
    """Offsets agree to 0.2 mm; arc lengths within |y| kappa h / 2 (a point at offset y from a bend of curvature
    kappa lands that far along a chord of length h), and areas to a millimetre squared."""
    exact = load_scene(name).tube
    sampled = exact.sampled(0.01)
    rng = np.random.default_rng(5)
    l_m = rng.uniform(0.0, exact.length_m, 200)
    y = rng.uniform(-0.9, 0.9, 200) * exact.half_width(l_m)
    points = (exact.center_at(l_m) + y[:, None] * exact.normal(l_m)).T
    a, b = sampled.project(points), exact.project(points)
    kappa = float(np.abs(exact.curvature(np.linspace(0.0, exact.length_m, 2000))).max())
    bound = np.abs(y) * kappa * 0.01 / 2 + 1e-6
    assert np.all(np.abs(a.l_m - b.l_m) <= bound) and np.abs(a.y_m - b.y_m).max() < 2e-4
    np.testing.assert_allclose(sampled.area(l_m), exact.area(l_m), rtol=0, atol=1e-3)


def test_the_half_widths_slope_is_each_intervals_and_zero_beyond_the_ends() -> None:
    """Oracle: the closed form of `straight`'s linear half-width (slope -1/8); on the Robotarium trapezoid sampled
    every centimetre, the exact tube's difference quotient over the interval holding l, and its own d lambda / dl
    at the intervals' midpoints (where the two agree to second order)."""
    tube = straight()
    l_m = np.array([-1.0, 0.0, 0.7, 2.0, 3.99, 4.0, 6.0])
    np.testing.assert_allclose(tube.half_width_slope(l_m), [0.0, -0.125, -0.125, -0.125, -0.125, 0.0, 0.0])
    exact = load_scene('robotarium_trapezoid').tube
    sampled = exact.sampled(0.01)
    l_m = np.random.default_rng(3).uniform(0.0, exact.length_m, 200)
    k = np.searchsorted(sampled.l_m, l_m, side='right') - 1
    start, end = sampled.l_m[k], sampled.l_m[k + 1]
    quotient = (np.asarray(exact.half_width(end)) - np.asarray(exact.half_width(start))) / (end - start)
    np.testing.assert_allclose(sampled.half_width_slope(l_m), quotient, atol=1e-9)
    midpoint = np.asarray(exact.half_width_slope(0.5 * (start + end)))
    np.testing.assert_allclose(sampled.half_width_slope(l_m), midpoint, atol=0.02)
    assert np.ptp(midpoint) > 0.5  # the narrowing's walls are steep: a slope-free answer fails
