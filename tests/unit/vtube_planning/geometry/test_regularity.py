"""The regularity conditions: R2 (lambda |kappa| < 1), R3 (no overlap), R4 (C^1 width), each failure naming where."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vtube_planning.errors import TubeError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.regularity import SLOPE_JUMP_TOL, check_grid, check_regularity
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile


def constant(length_m: float, half_width_m: float = 1.0) -> WidthProfile:
    return WidthProfile(half_width_m, (WidthPart('constant', length_m),))


# ---------------------------------------------------------------------- regularity


def test_over_curved_tube_names_the_arc_length() -> None:
    center = ArcPath((ArcPiece(4.0), ArcPiece(3.0, radius_m=2.0), ArcPiece(4.0)))
    with pytest.raises(TubeError, match=r'over-curved at l = 4\.000 m.*radius 2 m'):
        VirtualTube(center, constant(11.0, 2.5))


def test_self_intersecting_tube_names_both_arc_lengths() -> None:
    loop = ArcPath((ArcPiece(10.0), ArcPiece(3.0 * 1.5 * math.pi, radius_m=3.0), ArcPiece(10.0)))
    with pytest.raises(
        TubeError, match=r'overlaps itself: the cross-sections at l = \d+\.\d{3} m and l = \d+\.\d{3} m'
    ):
        VirtualTube(loop, constant(loop.length_m, 1.0))


def test_parallel_legs_overlap_only_when_over_curved() -> None:
    # a U-turn of radius 1.5 m: parallel legs 3 m apart overlap exactly when lambda > R, caught as folding
    hairpin = ArcPath((ArcPiece(10.0), ArcPiece(1.5 * math.pi, radius_m=1.5), ArcPiece(10.0)))
    with pytest.raises(TubeError, match=r'over-curved at l = 10\.000 m'):
        VirtualTube(hairpin, constant(hairpin.length_m, 1.6))
    VirtualTube(hairpin, constant(hairpin.length_m, 1.4))  # 2.8 m of tube in 3 m: regular


def test_converging_legs_overlap_although_locally_regular() -> None:
    # a 190 degree turn of radius 3 m: the legs converge to 4.2 m apart, lambda kappa stays below 1
    turn = ArcPath((ArcPiece(10.0), ArcPiece(3.0 * math.radians(190.0), radius_m=3.0), ArcPiece(10.0)))
    with pytest.raises(TubeError, match='overlaps itself'):
        VirtualTube(turn, constant(turn.length_m, 2.9))  # lambda kappa = 0.97, 5.8 m of tube in 4.2 m
    VirtualTube(turn, constant(turn.length_m, 1.5))  # 3 m of tube in 4.2 m: regular


def test_the_check_grid_is_four_times_finer_and_brackets_every_breakpoint() -> None:
    center = ArcPath((ArcPiece(4.0), ArcPiece(3.0, radius_m=5.0), ArcPiece(4.0)))
    width = WidthProfile(
        1.0, (WidthPart('constant', 2.5), WidthPart('smooth', 1.0, to_m=0.8), WidthPart('constant', 7.5))
    )
    samples = np.linspace(0.0, 11.0, 12)
    grid = check_grid(center, width, samples)
    assert grid[0] == 0.0 and grid[-1] == 11.0 and np.all(np.diff(grid) > 0)
    assert set(np.linspace(0.0, 11.0, 45)) <= set(grid)
    for knot in (2.5, 3.5, 4.0, 7.0):
        assert np.any(grid < knot) and np.min(np.abs(grid - (knot - 1e-8))) < 2e-8  # just before
        assert np.min(np.abs(grid - (knot + 1e-8))) < 2e-8  # and just after


def test_a_regular_tube_passes_and_the_name_is_in_every_message() -> None:
    center = ArcPath((ArcPiece(4.0), ArcPiece(3.0, radius_m=2.0), ArcPiece(4.0)))
    samples = np.linspace(0.0, 11.0, 111)
    check_regularity(center, constant(11.0, 1.9), samples, 'fine')  # lambda kappa = 0.95 < 1
    with pytest.raises(TubeError, match=r"^tube 'bent' is over-curved at l = 4\.000 m"):
        check_regularity(center, constant(11.0, 2.0), samples, 'bent')  # lambda kappa = 1
    kinked = WidthProfile(1.0, (WidthPart('linear', 5.0, to_m=0.5, corner_m=0.0), WidthPart('constant', 6.0)))
    with pytest.raises(
        TubeError, match=r"^tube 'kink': the half-width is not C\^1 at l = 5\.000 m \(slope jumps by \+0\.1\)"
    ):
        check_regularity(center, kinked, samples, 'kink')
    assert SLOPE_JUMP_TOL < 1e-6
