"""The search grid and the centre curve: the grid's room is a lower bound of the obstacles' clearance, the path keeps
the room, and the lines and arcs pass through the path's ends with their turns no tighter than the limit."""

from __future__ import annotations

import itertools
import math

import numpy as np

from tests.unit.vtube_planning.geometry.from_maps.test_generate import spec, wall_with_gap
from vtube_planning.geometry.from_maps.centre_path import (
    SearchGrid,
    _pulled_straight,
    _segment_room,
    _segment_rooms,
    centre_curve,
)


def test_the_grid_room_is_a_lower_bound_and_the_path_keeps_it() -> None:
    tube_spec = spec(wall_with_gap(4.0, 7.0))
    grid = SearchGrid(tube_spec)
    rng = np.random.default_rng(8)
    points = rng.uniform([0.5, 0.5], [19.5, 9.5], size=(3000, 2))
    assert np.all(grid.room(points) <= tube_spec.obstacles.clearance(points) + 1e-9)  # the edge is the search's
    path = grid.path()
    assert np.allclose(path[0], tube_spec.start_m) and np.allclose(path[-1], tube_spec.goal_m)
    assert np.all(tube_spec.obstacles.clearance(path) >= tube_spec.room_m - 1e-9)
    corners, center = centre_curve(path, grid)
    assert len(corners) < len(path) / 10  # the grid's staircase is gone
    ends = center.frame(np.array([0.0, center.length_m]))[0]
    np.testing.assert_allclose(ends, [tube_spec.start_m, tube_spec.goal_m], atol=1e-9)
    radii = [piece.radius_m for piece in center.pieces if piece.radius_m is not None]
    assert radii and min(radii) >= tube_spec.turn_radius_min_m


def test_segments_share_one_lookup_and_the_path_pulled_straight_sees_as_far_as_it_can() -> None:
    tube_spec = spec(wall_with_gap(4.0, 7.0))
    grid = SearchGrid(tube_spec)
    path = grid.path()
    a, ends = path[0], path[1:40]
    rooms = _segment_rooms(a, ends, grid)
    np.testing.assert_array_equal(rooms[::-1], _segment_rooms(a, ends[::-1], grid))  # each its own, to the bit
    assert [_segment_room(a, end, grid) for end in ends] == rooms.tolist()
    for end, room in zip(ends, rooms, strict=True):  # a fifth of a cell apart, less half that: a lower bound
        length = float(np.hypot(*(end - a)))
        n = max(2, math.ceil(length / (0.2 * tube_spec.resolution_m)) + 1)
        samples = a + np.linspace(0.0, 1.0, n)[:, None] * (end - a)
        assert room == grid.room(samples).min() - 0.5 * length / (n - 1)
        along = a + np.linspace(0.0, 1.0, 200)[:, None] * (end - a)
        assert room <= tube_spec.obstacles.clearance(along).min() + 1e-9
    kept = _pulled_straight(path, grid)
    index = [int(np.flatnonzero(np.all(path == vertex, axis=1))[0]) for vertex in kept]
    assert index[0] == 0 and index[-1] == len(path) - 1 and len(index) < len(path) / 10
    for i, j in itertools.pairwise(index):  # each hop keeps the room, and one vertex farther would not
        assert _segment_room(path[i], path[j], grid) >= tube_spec.room_m or j == i + 1
        assert j + 1 == len(path) or _segment_room(path[i], path[j + 1], grid) < tube_spec.room_m
