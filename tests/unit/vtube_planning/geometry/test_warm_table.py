"""WarmTable: the bounds that certify a warm projection, checked against brute force on small tubes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.warm_table import WarmTable, ray_distance
from vtube_planning.geometry.width import WidthPart, WidthProfile


def table_of(center: ArcPath, half_width: float, spacing: float = 0.05) -> WarmTable:
    samples = np.linspace(0.0, center.length_m, round(center.length_m / spacing) + 1)
    width = WidthProfile(half_width, (WidthPart('constant', center.length_m),))
    points = center.frame(samples)[0]
    return WarmTable.of(center, width, samples, cKDTree(points))


def test_ray_distance_is_the_distance_to_the_half_line() -> None:
    points = np.array([[3.0, 4.0], [-2.0, 1.0], [1.0, -1.0]])
    d = ray_distance(points, np.array([0.0, 0.0]), np.array([1.0, 0.0]), np.array([0.0, 0.0, 2.0]))
    # (3, 4): foot (3, 0) -> 4; (-2, 1): before the ray -> distance to (0, 0); (1, -1) with the ray from x = 2
    np.testing.assert_allclose(d, [4.0, math.sqrt(5.0), math.sqrt(2.0)])


def test_the_far_bound_is_below_every_far_distance_on_a_hairpin() -> None:
    """A U-turn (straight, half circle of radius 2, straight back): the legs come 4 m close; T_i must not exceed
    the true distance from gamma(s_i) to any curve point (or extension) at least W away in arc length."""
    center = ArcPath((ArcPiece(6.0), ArcPiece(2.0 * math.pi, radius_m=2.0), ArcPiece(6.0)))
    table = table_of(center, 0.8)
    assert table.window_m == pytest.approx(2 * 0.8 + 3 * np.diff(table.l_m).max(), rel=1e-12)
    fine = np.linspace(-15.0, center.length_m + 15.0, 6000)  # the curve and both straight extensions
    inner = np.clip(fine, 0.0, center.length_m)
    pos, tan, _ = center.frame(inner)
    curve = pos + (fine - inner)[:, None] * tan
    for i in range(0, table.l_m.size, 7):
        far = np.abs(fine - table.l_m[i]) >= table.window_m
        true = np.hypot(*(curve[far] - table.points[i]).T).min()
        assert table.far_m[i] <= true + 1e-9
    middle = table.nearest_sample(np.array([3.0]))[0]
    assert table.far_m[middle] < 4.5  # the other leg is 4 m across: the bound sees it


def test_the_curvature_bound_covers_the_window_and_is_exact_on_arcs() -> None:
    center = ArcPath((ArcPiece(10.0), ArcPiece(3.0, radius_m=4.0, left=False), ArcPiece(10.0)))
    table = table_of(center, 1.0, spacing=0.1)
    reach = table.window_m + 0.1
    kappa = np.where((table.l_m > 10.0 - reach) & (table.l_m < 13.0 + reach), 0.25, 0.0)
    far_from_arc = (table.l_m < 10.0 - reach - 0.2) | (table.l_m > 13.0 + reach + 0.2)
    assert np.all(table.kappa_max[kappa > 0] == pytest.approx(0.25))
    assert np.all(table.kappa_max[far_from_arc] == 0.0)


def test_nearest_sample_and_contiguous_coordinates() -> None:
    table = table_of(ArcPath((ArcPiece(1.0),), (2.0, 3.0), 0.0), 0.5, spacing=0.25)
    assert table.nearest_sample(np.array([-1.0, 0.1, 0.13, 0.6, 2.0])).tolist() == [0, 0, 1, 2, 4]
    np.testing.assert_allclose(table.x_m, 2.0 + table.l_m)
    np.testing.assert_allclose(table.y_m, 3.0)
    assert table.x_m.flags.c_contiguous and table.y_m.flags.c_contiguous
