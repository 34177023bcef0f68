"""The tube's tables: points located as the exact projection locates them, rows interpolated as np.interp does."""

from __future__ import annotations

import numpy as np
import pytest

from tests.unit.vtube_planning.swarm.test_foresight import BENT, STRAIGHT
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.swarm.tube_tables import TubeTables


@pytest.mark.parametrize('tube', [STRAIGHT, BENT], ids=['straight', 'bent'])
def test_the_tables_locate_points_as_the_projection_does(tube: VirtualTube) -> None:
    tables = TubeTables.of(tube, 5.0)
    rng = np.random.default_rng(3)
    l_true = rng.uniform(0.0, tube.length_m, 500)
    y_true = rng.uniform(-0.95, 0.95, 500) * np.asarray(tube.half_width(l_true))
    points = tube.center_at(l_true).T + y_true * tube.normal(l_true).T
    l_m, offset = tables.locate(points[0], points[1], l_true + rng.uniform(-1.0, 1.0, 500))  # a guess 1 m off
    exact = tube.project(points)
    np.testing.assert_allclose(l_m, exact.l_m, atol=2e-3)
    np.testing.assert_allclose(offset, exact.y_m, atol=2e-3)
    clearance = tables.clearance(l_m, offset)
    np.testing.assert_allclose(clearance, exact.clearance_m, atol=3e-3)
    assert np.isinf(tables.clearance(np.array([-1.0, tube.length_m + 1.0]), np.zeros(2))).all()


def test_the_tables_interpolate_as_np_interp_does_and_hold_the_ends() -> None:
    tables = TubeTables.of(BENT, 5.0, window_m=3.0)
    l_m = np.random.default_rng(5).uniform(-8.0, BENT.length_m + 8.0, 400)  # beyond the tables' span too
    at = tables.at(l_m, slice(0, 5))
    for row in range(5):
        np.testing.assert_allclose(at[row], np.interp(l_m, tables.l_m, tables.stacked[row]), rtol=0, atol=1e-12)


def test_the_guess_is_the_nearest_table_point_and_a_lane_is_the_offset_over_the_room() -> None:
    tables = TubeTables.of(BENT, 5.0, window_m=2.0)
    rng = np.random.default_rng(6)
    positions = np.vstack([rng.uniform(-10.0, 40.0, 300), rng.uniform(-15.0, 25.0, 300)])
    squared = ((positions[:, :, None] - tables.stacked[:2, None, :]) ** 2).sum(axis=0)  # brute force
    np.testing.assert_array_equal(tables.nearest_l(positions), tables.l_m[squared.argmin(axis=1)])
    l_m, offset = rng.uniform(-3.0, BENT.length_m + 3.0, 300), rng.uniform(-3.0, 3.0, 300)
    room = np.maximum(tables.at(l_m, slice(4, 5))[0] - 0.4, 1e-9)
    np.testing.assert_array_equal(tables.lane_of(l_m, offset, 0.4), np.clip(offset / room, -1.0, 1.0))
