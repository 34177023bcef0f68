"""The widest turn through each bend of a tube: where no path inside it turns no tighter than a radius.

A robot held to (2) and (4), v >= v_min and |v|^2 / r <= a_n, turns no tighter than R_min = v_min^2 / a_n, whatever
its controller. A bend of the tube (an arc of an `ArcPath` between two straight pieces, or the tube's straight
continuations past its ends) of centre radius R and turning angle theta, with room h for a robot's centre from the
walls (the largest half-width around it less the robot's radius r_p), lets through no curve of radius larger than

    R_fit = R + h cot^2(theta / 4),

the circle tangent to both outer walls that touches the inner wall (``docs/theory.md`` §3.6). The bound counts only
where the straights on both sides are long enough for that circle to reach its tangent points; elsewhere (an S-bend
whose straight is shorter, a spline centre line, a turn of pi or more) nothing is claimed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vtube_planning.geometry.centerline import ArcPath
from vtube_planning.geometry.tube import VirtualTube

SAMPLES_PER_M = 100
"""Half-width samples per metre of a bend and its straights (with the width profile's breakpoints)."""


@dataclass(frozen=True)
class Bend:
    """An arc of the centre line between straights: where it runs (m), its centre radius (m), its turning angle
    (rad, in (0, pi)), the straights before and after it (m; 0 where the tube ends: past its ends no robot is held to
    it)."""

    start_m: float
    end_m: float
    radius_m: float
    angle_rad: float
    before_m: float
    after_m: float

    def widest_radius_m(self, room_m: float) -> float:
        """R_fit = R + h cot^2(theta / 4): the largest circle through the bend with ``room_m`` (h) for a robot's
        centre on each side of the centre line."""
        return self.radius_m + room_m / math.tan(self.angle_rad / 4.0) ** 2

    def straight_needed_m(self, radius_m: float, room_m: float) -> float:
        """How long each straight must be for a circle of ``radius_m`` tangent to both outer walls to touch them:
        (radius - R - h) tan(theta / 2), 0 when the outer wall itself is wide enough."""
        return max(0.0, radius_m - self.radius_m - room_m) * math.tan(self.angle_rad / 2.0)


def bends(tube: VirtualTube) -> tuple[Bend, ...]:
    """The tube's bends: each arc of an `ArcPath` centre line that turns less than pi between straight pieces or the
    tube's ends (none for other centre curves)."""
    center = tube.center
    if not isinstance(center, ArcPath):
        return ()
    pieces = center.pieces
    starts = np.concatenate([[0.0], np.cumsum([p.length_m for p in pieces])])
    found = []
    for k, piece in enumerate(pieces):
        angle = piece.length_m / piece.radius_m if piece.radius_m is not None else 0.0
        if piece.radius_m is None or angle >= math.pi:
            continue
        sides = [0.0 if j < 0 or j >= len(pieces) else pieces[j] for j in (k - 1, k + 1)]
        if any(not isinstance(s, float) and s.radius_m is not None for s in sides):
            continue
        before, after = (s if isinstance(s, float) else s.length_m for s in sides)
        found.append(Bend(float(starts[k]), float(starts[k + 1]), piece.radius_m, angle, before, after))
    return tuple(found)


def room_m(tube: VirtualTube, bend: Bend, reach_m: float, body_radius_m: float) -> float:
    """The room h of a robot's centre around ``bend``: the largest half-width over the bend and ``reach_m`` of
    tube on each side (the tube's end half-widths past its ends), less ``body_radius_m``."""
    low, high = bend.start_m - reach_m, bend.end_m + reach_m
    l_m = np.linspace(low, high, max(2, math.ceil((high - low) * SAMPLES_PER_M) + 1))
    knots = tube.width.breakpoints
    l_m = np.clip(np.concatenate([l_m, knots[(knots > low) & (knots < high)]]), 0.0, tube.length_m)
    return float(np.max(tube.half_width(l_m))) - body_radius_m


def too_tight(tube: VirtualTube, turn_radius_m: float, body_radius_m: float) -> str | None:
    """Why no robot that turns no tighter than ``turn_radius_m`` passes the tube, and the fix, or None: the first
    bend whose widest circle (with straights long enough to hold it) is smaller (module doc)."""
    for bend in bends(tube):
        reach = bend.straight_needed_m(turn_radius_m, 0.0)
        room = room_m(tube, bend, reach, body_radius_m)
        widest = bend.widest_radius_m(room)
        if widest >= turn_radius_m or min(bend.before_m, bend.after_m) < bend.straight_needed_m(turn_radius_m, room):
            continue
        factor = 1.0 / math.tan(bend.angle_rad / 4.0) ** 2
        half = (turn_radius_m - bend.radius_m) / factor + body_radius_m
        radius = turn_radius_m - max(0.0, room) * factor
        widen = f'widen the tube there to {2.0 * half:.4g} m or ' if half < bend.radius_m else ''
        return (
            f'the bend at l = {bend.start_m:.3f}..{bend.end_m:.3f} m (centre radius {bend.radius_m:g} m, turning '
            f'{math.degrees(bend.angle_rad):.4g} deg) lets no robot through that turns no tighter than '
            f'v_min^2 / a_n = {turn_radius_m:.4g} m: the widest curve between its walls has radius {widest:.4g} m; '
            f'{widen}make the centre radius at least {radius:.4g} m'
        )
    return None
