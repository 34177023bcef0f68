"""The initial formation: a grid of spacing 2 r_a before the entrance, as wide as the entrance allows, or the
positions given."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vtube_planning.errors import ParamsError, ShapeError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.params import SwarmParams
from vtube_planning.swarm.formation import as_positions, initial_formation, start_formation


def tube(half_width_m: float, heading: float = 0.0) -> VirtualTube:
    return VirtualTube(
        ArcPath((ArcPiece(20.0),), (1.0, -1.0), heading), WidthProfile(half_width_m, (WidthPart('constant', 20.0),))
    )


def in_tube_coordinates(t: VirtualTube, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    p = t.project(points)
    return p.l_m, p.y_m


def test_a_wide_entrance_takes_n_side_columns_in_rows_2_r_a_apart() -> None:
    swarm = SwarmParams(n_robots=10)  # n_side 4: rows of 4, 4, 2
    t = tube(10.0, heading=0.4)
    l_m, y_m = in_tube_coordinates(t, initial_formation(t, swarm, np.random.default_rng(0), 0.0))
    r_a = swarm.r_a_m
    np.testing.assert_allclose(l_m, np.repeat([-r_a, -3 * r_a, -5 * r_a], [4, 4, 2]), atol=1e-9)
    np.testing.assert_allclose(y_m[:4], 2 * r_a * np.array([-1.5, -0.5, 0.5, 1.5]), atol=1e-9)
    np.testing.assert_allclose(y_m[8:], 2 * r_a * np.array([-0.5, 0.5]), atol=1e-9)  # the last row centred


def test_a_narrow_entrance_takes_as_many_columns_as_fit_with_r_a_to_spare() -> None:
    swarm = SwarmParams(n_robots=9)  # r_a = 0.8: half-width 2 fits floor(2 (2 - 0.8) / 1.6) + 1 = 2 columns
    t = tube(2.0)
    l_m, y_m = in_tube_coordinates(t, initial_formation(t, swarm, np.random.default_rng(0), 0.0))
    np.testing.assert_allclose(y_m, [-0.8, 0.8] * 4 + [0.0], atol=1e-9)  # the ninth robot alone, centred
    assert np.all(np.abs(y_m) + swarm.r_a_m <= 2.0 + 1e-9)
    assert len(set(np.round(l_m, 9))) == math.ceil(9 / 2)


def test_the_jitter_is_gaussian_with_the_stated_deviation_and_follows_the_seed() -> None:
    swarm = SwarmParams(n_robots=400)
    t = tube(40.0)
    exact = initial_formation(t, swarm, np.random.default_rng(0), 0.0)
    jittered = initial_formation(t, swarm, np.random.default_rng(7), 0.05)
    offsets = (jittered - exact).ravel()
    assert abs(offsets.mean()) < 0.01 and offsets.std() == pytest.approx(0.05, rel=0.1)
    np.testing.assert_array_equal(jittered, initial_formation(t, swarm, np.random.default_rng(7), 0.05))


def test_an_entrance_too_narrow_for_one_robot_is_named() -> None:
    with pytest.raises(ParamsError, match=r'the entrance \(half-width 0.5 m\) is too narrow .* r_a = 0.8 m'):
        initial_formation(tube(0.5), SwarmParams(), np.random.default_rng(0), 0.0)


def test_given_positions_are_flown_as_given_one_per_robot() -> None:
    """Any (2, N) array-like becomes two rows of floats; the start is exactly those points (no jitter, no grid)."""
    t = tube(10.0)
    given = as_positions(np.array([[-0.5, -0.5, -0.9], [0.2, -0.2, 0.0]]))
    assert (
        given == ((-0.5, -0.5, -0.9), (0.2, -0.2, 0.0)) and as_positions([[-0.5, -0.5, -0.9], [0.2, -0.2, 0]]) == given
    )
    start = start_formation(t, SwarmParams(n_robots=3), given, 7, 0.05)
    np.testing.assert_array_equal(start, np.array(given))
    grid = start_formation(t, SwarmParams(n_robots=3), None, 7, 0.05)
    same = initial_formation(t, SwarmParams(n_robots=3), np.random.default_rng(7), 0.05)
    np.testing.assert_array_equal(grid, same)  # nothing given: the grid, drawn as before
    with pytest.raises(ParamsError, match=r'3 initial positions were given for a swarm of 4 robots; .* fly 3 robots'):
        start_formation(t, SwarmParams(n_robots=4), given, 0, 0.0)


@pytest.mark.parametrize(
    ('value', 'problem'),
    [
        (np.zeros((3, 2)), r'must have shape \(2, N\) with N >= 1'),
        (np.zeros((2, 0)), r'must have shape \(2, N\) with N >= 1'),
        (np.zeros(2), r'must have shape \(2, N\)'),
        (np.array([[0.0, np.nan], [0.0, 0.0]]), r'must be finite; robots \[1\] contain NaN'),
    ],
)
def test_bad_given_positions_are_named(value: np.ndarray, problem: str) -> None:
    with pytest.raises(ShapeError, match=problem):
        as_positions(value)
