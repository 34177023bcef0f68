"""The widest turn through a bend: the circle of R + h cot^2(theta / 4) just fits, and nothing that fits is refused."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from vtube_planning.geometry.bends import Bend, bends, too_tight
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.scene import load_scene
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile

R_P = 0.3


def bend_tube(radius_m: float, angle_rad: float, half_width_m: float, straight_m: float = 60.0) -> VirtualTube:
    """A straight, a left arc, a straight, of constant half-width."""
    pieces = (ArcPiece(straight_m), ArcPiece(radius_m * angle_rad, radius_m), ArcPiece(straight_m))
    length = sum(p.length_m for p in pieces)
    return VirtualTube(ArcPath(pieces), WidthProfile(half_width_m, (WidthPart('constant', length),)))


def circle_clearance(tube: VirtualTube, radius_m: float) -> float:
    """The least clearance (distance inside the wall) of the circle of ``radius_m`` tangent to both outer walls of
    the tube's one bend moved in by R_P (where a robot's centre may go), between its two tangent points (built from
    the tube's own frame and projection, not from the formula)."""
    (bend,) = bends(tube)
    start, end = tube.center_at(bend.start_m), tube.center_at(bend.end_m)
    centre = start + bend.radius_m * tube.normal(bend.start_m)  # the arc's centre O (a left turn)
    mid = tube.center_at(0.5 * (bend.start_m + bend.end_m))
    axis = (mid - centre) / np.linalg.norm(mid - centre)
    outer = bend.radius_m + float(tube.half_width(0.0)) - R_P
    d = (radius_m - outer) / math.cos(bend.angle_rad / 2.0)  # tangent to the lines at R + lambda - r_p
    c = centre - d * axis
    u1, u2 = (start - centre) / bend.radius_m, (end - centre) / bend.radius_m
    a1, a2 = math.atan2(u1[1], u1[0]), math.atan2(u2[1], u2[0])
    phi = np.linspace(a1, a1 + (a2 - a1 + math.pi) % (2 * math.pi) - math.pi, 4001)
    points = c[:, None] + radius_m * np.vstack([np.cos(phi), np.sin(phi)])
    found = tube.project(points)
    return float(np.min(found.half_width_m - np.abs(found.y_m)))


@pytest.mark.parametrize(('radius', 'degrees', 'half'), [(3.0, 90.0, 1.0), (2.0, 120.0, 0.8), (6.0, 45.0, 0.5)])
def test_the_widest_circle_just_fits(radius: float, degrees: float, half: float) -> None:
    tube = bend_tube(radius, math.radians(degrees), half)
    (bend,) = bends(tube)
    widest = bend.widest_radius_m(half - R_P)
    assert circle_clearance(tube, widest) == pytest.approx(R_P, abs=1e-6)  # touches the walls, stays inside
    assert circle_clearance(tube, widest * 1.01) < R_P - 1e-4  # a wider one cuts the inner wall
    assert too_tight(tube, widest * 0.999, R_P) is None
    refused = too_tight(tube, widest * 1.001, R_P)
    assert refused is not None and f'{bend.start_m:.3f}' in refused


def test_the_fixes_it_names_let_the_turn_through() -> None:
    tube = bend_tube(3.0, math.radians(90.0), 0.5)
    turn = 5.0
    refused = too_tight(tube, turn, R_P)
    assert refused is not None
    found = re.findall(r'to ([\d.]+) m or make the centre radius at least ([\d.]+) m', refused)
    width, radius = (float(x) for x in found[0])
    assert too_tight(bend_tube(3.0, math.radians(90.0), width / 2 * 1.001), turn, R_P) is None
    assert too_tight(bend_tube(3.0, math.radians(90.0), width / 2 * 0.999), turn, R_P) is not None
    assert too_tight(bend_tube(radius * 1.001, math.radians(90.0), 0.5), turn, R_P) is None
    assert too_tight(bend_tube(radius * 0.999, math.radians(90.0), 0.5), turn, R_P) is not None


def test_a_straight_tube_is_never_refused() -> None:
    tube = VirtualTube(ArcPath((ArcPiece(40.0),)), WidthProfile(0.31, (WidthPart('constant', 40.0),)))
    assert bends(tube) == ()
    assert too_tight(tube, 1e6, R_P) is None


def test_a_tube_with_a_feasible_path_is_never_refused() -> None:
    """Random bends, each with a path built inside it: its own centre line (radius R), or the widest circle; a turn
    no wider than that path's radius is never refused, whatever the straights."""
    rng = np.random.default_rng(7)
    for _ in range(60):
        radius, angle = rng.uniform(1.0, 20.0), rng.uniform(0.1, 0.95 * math.pi)
        half = rng.uniform(R_P + 0.05, min(3.0, 0.9 * radius))
        straight = rng.uniform(0.5, 40.0)
        tube = bend_tube(radius, angle, half, straight)
        assert too_tight(tube, radius, R_P) is None  # the centre line itself turns at R
        (bend,) = bends(tube)
        widest = bend.widest_radius_m(half - R_P)
        assert too_tight(tube, widest * (1 - 1e-9), R_P) is None
        if min(bend.before_m, bend.after_m) >= bend.straight_needed_m(widest * 1.01, half - R_P):
            assert too_tight(tube, widest * 1.01, R_P) is not None


def test_a_bend_at_the_tube_end_or_beside_another_arc_is_not_judged() -> None:
    pieces = (ArcPiece(2.0 * math.pi / 2, 2.0), ArcPiece(3.0 * math.pi / 2, 3.0, left=False), ArcPiece(20.0))
    length = sum(p.length_m for p in pieces)
    tube = VirtualTube(ArcPath(pieces), WidthProfile(0.5, (WidthPart('constant', length),)))
    assert bends(tube) == ()  # the first is at the entrance, the second beside an arc: nothing proven
    assert too_tight(tube, 100.0, R_P) is None


def test_the_shipped_scenes_pass() -> None:
    for name in 'ABCD':
        scene = load_scene(name)
        assert too_tight(scene.tube, scene.swarm.v_min_mps**2 / scene.swarm.a_n_mps2, scene.swarm.r_p_m) is None


def test_a_bend_knows_its_straights() -> None:
    bend = Bend(10.0, 12.0, 2.0, math.pi / 2, 10.0, 5.0)
    assert bend.widest_radius_m(0.0) == 2.0
    assert bend.straight_needed_m(5.0, 1.0) == pytest.approx(2.0)
    assert bend.straight_needed_m(2.5, 1.0) == 0.0
