"""Shapes: the exact clearance against a brute-force one, and the obstacles kept near a block of points, which
must leave every point's clearance the same to the bit while dropping the far ones."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from vtube_planning.geometry._shapes import Shapes


def random_shapes(rng: np.random.Generator, discs: int, polygons: int, size: float = 40.0) -> Shapes:
    """Discs and rotated rectangles or random star polygons (possibly overlapping) in a size x size square."""
    made = [
        ((float(x), float(y)), float(r))
        for x, y, r in zip(*rng.uniform(0.0, size, (2, discs)), rng.uniform(0.3, 3.0, discs), strict=True)
    ]
    shapes = []
    for _ in range(polygons):
        k = int(rng.integers(3, 9))
        angles = np.sort(rng.uniform(0.0, 2.0 * math.pi, k))
        radii = rng.uniform(0.5, 4.0, k)
        center = rng.uniform(0.0, size, 2)
        shapes.append(center + np.column_stack([radii * np.cos(angles), radii * np.sin(angles)]))
    return Shapes.of(made, shapes)


def brute_force(shapes: Shapes, p: np.ndarray) -> np.ndarray:
    """Point by point, edge by edge, in plain floats: 0 inside a disc or (even-odd) a polygon, else the distance."""
    out = np.full(len(p), math.inf)
    starts = np.concatenate([[0], np.cumsum(shapes.counts)])
    for n, (x, y) in enumerate(p):
        best = math.inf
        for (cx, cy), r in zip(shapes.centers, shapes.radii, strict=True):
            best = min(best, max(math.hypot(x - cx, y - cy) - r, 0.0))
        for first, last in itertools.pairwise(starts):
            inside, nearest = False, math.inf
            for (ax, ay), (dx, dy) in zip(shapes.a[first:last], shapes.d[first:last], strict=True):
                t = min(max(((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy), 0.0), 1.0)
                nearest = min(nearest, math.hypot(x - ax - t * dx, y - ay - t * dy))
                if (ay <= y) != (ay + dy <= y) and x < ax + (y - ay) * dx / dy:
                    inside = not inside
            best = min(best, 0.0 if inside else nearest)
        out[n] = best
    return out


@pytest.mark.parametrize('seed', range(4))
def test_the_clearance_matches_a_brute_force_one(seed: int) -> None:
    rng = np.random.default_rng(seed)
    shapes = random_shapes(rng, 6, 6, size=12.0)
    points = rng.uniform(-2.0, 14.0, size=(400, 2))
    clearance = shapes.clearance(points)
    np.testing.assert_allclose(clearance, brute_force(shapes, points), rtol=0.0, atol=1e-12)
    assert (clearance == 0.0).any() and (clearance > 0.0).any()  # both inside and outside were tried


@pytest.mark.parametrize('seed', range(20))
def test_what_is_kept_near_a_block_gives_every_point_the_same_clearance(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    shapes = random_shapes(rng, int(rng.integers(0, 25)), int(rng.integers(0, 25)))
    spread = float(rng.choice([0.05, 1.0, 5.0, 40.0]))
    block = rng.uniform(-5.0, 45.0, 2) + rng.uniform(0.0, spread, size=(int(rng.integers(1, 300)), 2))
    near = shapes.near(block)
    np.testing.assert_array_equal(near.clearance(block), shapes.clearance(block))  # to the bit


def test_a_block_keeps_only_the_obstacles_near_it() -> None:
    rng = np.random.default_rng(7)
    shapes = random_shapes(rng, 30, 30, size=80.0)
    along = np.column_stack([np.linspace(10.0, 12.0, 256), np.full(256, 20.0)])  # a 2 m piece of a curve
    near = shapes.near(along)
    assert near.radii.size + near.counts.size < 10 < shapes.radii.size + shapes.counts.size
    np.testing.assert_array_equal(near.clearance(along), shapes.clearance(along))
    assert near.near(along[:1]).clearance(along[:1]) == shapes.clearance(along[:1])


def test_points_not_finite_keep_everything_and_no_shapes_are_inf_away() -> None:
    shapes = random_shapes(np.random.default_rng(8), 3, 3)
    assert shapes.near(np.array([[np.nan, 1.0]])) is shapes
    assert np.isinf(Shapes.of([], []).clearance(np.array([[0.0, 0.0], [5.0, 5.0]]))).all()


def test_one_polygon_alone() -> None:
    rng = np.random.default_rng(9)
    shapes = random_shapes(rng, 2, 4)
    points = rng.uniform(0.0, 40.0, size=(200, 2))
    first = shapes.counts[0]
    alone = Shapes.of([], [shapes.a[:first]])
    np.testing.assert_array_equal(shapes.polygon(0).clearance(points), alone.clearance(points))
