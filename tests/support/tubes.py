"""Small analytic tubes for the geometry tests: an arc, a spline through waypoints, a constant width."""

from __future__ import annotations

import math

from vtube_planning.geometry.centerline import ArcPath, ArcPiece, SplineCurve
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile

WAYPOINTS = ((0.0, 0.0), (10.0, 1.0), (20.0, -1.0), (30.0, 0.0), (50.0, 0.0), (60.0, 1.0), (70.0, 0.0))


def constant(length_m: float, half_width_m: float = 1.0) -> WidthProfile:
    return WidthProfile(half_width_m, (WidthPart('constant', length_m),))


def straight_tube(length_m: float = 10.0, start=(1.0, -2.0), heading_deg: float = 30.0) -> VirtualTube:
    center = ArcPath((ArcPiece(length_m),), start, math.radians(heading_deg))
    return VirtualTube(center, constant(length_m, 1.5))


def arc_tube(radius_m: float = 5.0, angle_deg: float = 120.0, left: bool = True) -> VirtualTube:
    length = radius_m * math.radians(angle_deg)
    center = ArcPath((ArcPiece(length, radius_m=radius_m, left=left),))
    return VirtualTube(center, constant(length, 0.4 * radius_m))


def spline_tube() -> VirtualTube:
    center = SplineCurve(WAYPOINTS)
    width = WidthProfile(3.0, (WidthPart('smooth', 15.0, to_m=1.0), WidthPart('constant', center.length_m - 15.0)))
    return VirtualTube(center, width)
