"""Virtual tube geometry against analytic oracles, quadrature and finite differences."""

from __future__ import annotations

import math

import pytest

from vtube_planning.errors import TubeError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
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
