"""The start region, Oler's bound on it, and the packing in no rows (`robotarium_exp.packing`)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from robotarium_exp import design
from robotarium_exp.fit import robotarium_fit
from robotarium_exp.packing import (
    _PACKINGS,
    QUEUE_BEFORE_NARROWING_M,
    WALL_CLEARANCE_M,
    oler_bound,
    packed_poses,
    packing_bound,
)
from robotarium_exp.scene import load_scene
from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile, first_narrowing

SPACING = ROBOTARIUM.ic_spacing_m
BOX = np.array(ROBOTARIUM.ic_box_m)
SWEEP_TUBES = Path(__file__).parents[3] / 'docs' / 'sweep' / 'tubes'


def straight(half_width_m: float, length_m: float) -> VirtualTube:
    """A straight tube along x from the arena's left end (x = -1.45 m, outside the box), no narrowing."""
    center = ArcPath((ArcPiece(length_m),), (-1.45, 0.0), 0.0)
    return VirtualTube(center, WidthProfile(half_width_m, (WidthPart('constant', length_m),)))


def oler(a: float, b: float) -> int:
    """Oler's bound for an a x b rectangle, written out."""
    return math.floor(2.0 / math.sqrt(3.0) * a * b / SPACING**2 + (a + b) / SPACING + 1.0)


def test_the_bound_on_a_rectangle_is_olers_formula() -> None:
    """A straight tube entering outside the box: the region is the rectangle from the box's edge (x = -1.375 m) to
    the exit, 0.1 m inside the walls (behind the entrance it lies outside the box)."""
    for half_width, length in ((0.3, 1.1), (0.45, 1.6), (0.5, 2.0)):
        a, b = length - 0.075, 2.0 * (half_width - WALL_CLEARANCE_M)
        assert packing_bound(straight(half_width, length)) == oler(a, b), (half_width, length)


def test_the_bound_of_a_point_set_without_area_counts_along_its_segment() -> None:
    """No point: none; one: one; collinear points (a diagonal 1 m long, any direction): floor(1 / 0.4) + 1 = 3,
    as many as stand 0.4 m apart on it; a 0.45 m square: Oler's 4."""
    assert oler_bound(np.zeros((0, 2)), SPACING) == 0
    assert oler_bound(np.array([[0.3, -0.2]]), SPACING) == 1
    for angle in (0.0, 0.6, math.pi / 2):
        segment = np.outer(np.linspace(0.0, 1.0, 7), [math.cos(angle), math.sin(angle)])
        assert oler_bound(segment, SPACING) == 3
    square = np.array([[0.0, 0.0], [0.45, 0.0], [0.45, 0.45], [0.0, 0.45], [0.2, 0.2]])
    assert oler_bound(square, SPACING) == oler(0.45, 0.45) == 4


def test_a_square_holds_its_four_corners_and_not_five() -> None:
    """A 0.45 m square region: four robots at its corners, 0.45 m apart; Oler's bound is 4, so five are refused
    without a search; one robot anywhere in it."""
    t = straight(0.325, 0.525)
    assert packing_bound(t) == 4 == oler(0.45, 0.45)
    one = packed_poses(t, 1)
    assert one is not None
    assert_in_the_start_region(t, one)
    poses = packed_poses(t, 4)
    assert poses is not None
    assert gaps(poses).min() >= SPACING
    assert packed_poses(t, 5) is None


def gaps(poses: np.ndarray) -> np.ndarray:
    n = poses.shape[1]
    return np.hypot(*(poses[:2, :, None] - poses[:2, None, :]))[np.triu_indices(n, 1)]


def assert_in_the_start_region(t: VirtualTube, poses: np.ndarray) -> None:
    """Every robot 0.4 m from every other, inside the box, 0.1 m inside the walls, before the narrowing (less its
    margin), facing along the tube."""
    where = t.project(poses[:2])
    narrowing = first_narrowing(*t.width.knots)
    end = narrowing.start_m - QUEUE_BEFORE_NARROWING_M if narrowing is not None else t.length_m
    assert gaps(poses).min() >= SPACING if poses.shape[1] > 1 else True
    assert np.all(np.abs(poses[:2].T) <= BOX)
    assert np.all(where.l_m <= end + 1e-9)
    room = np.asarray(t.half_width(np.maximum(where.l_m, 0.0))) - WALL_CLEARANCE_M
    assert np.all(np.abs(where.y_m) <= room + 1e-9)
    tangent = t.tangent(where.l_m)
    heading = np.arctan2(tangent[:, 1], tangent[:, 0])
    np.testing.assert_allclose(np.angle(np.exp(1j * (poses[2] - heading))), 0.0, atol=1e-7)


@pytest.mark.parametrize(('name', 'n'), [('bend35', 10), ('bend60', 10), ('s_curve', 11)])
def test_the_sweep_bends_pack_more_than_their_rows(name: str, n: int) -> None:
    """Where rows, the queue and staggered rows reach the narrowing (the sweep refused these before), the packing
    holds them, in the start region, at most Oler's bound; the search is deterministic."""
    t = load_scene(SWEEP_TUBES / f'{name}.toml', n_robots=2).tube
    formation = design.start_formation(t, n)
    assert formation.packed and formation.problem is None
    assert_in_the_start_region(t, formation.poses)
    assert n <= packing_bound(t)
    _PACKINGS.clear()
    again = design.start_formation(t, n)
    np.testing.assert_array_equal(again.poses, formation.poses)


def test_packing_is_the_last_resort(monkeypatch: pytest.MonkeyPatch) -> None:
    """A packed formation only where the formations before it (rows, queue, staggered rows) all reach the
    narrowing: without the packing the same tubes and N give formations past it, and every other formation is
    unchanged."""
    cases = [(load_scene(path, n_robots=2).tube, n) for path in sorted(SWEEP_TUBES.glob('*.toml')) for n in (8, 10)]
    with_packing = [design.start_formation(t, n) for t, n in cases]
    monkeypatch.setattr(design, 'packed_poses', lambda *_: None)
    for (t, n), formation in zip(cases, with_packing, strict=True):
        without = design.start_formation(t, n)
        narrowing = first_narrowing(*t.width.knots)
        if formation.packed:
            assert narrowing is not None and without.l_front_m > narrowing.start_m
        else:
            np.testing.assert_array_equal(without.poses, formation.poses)
    assert any(f.packed for f in with_packing)


def random_tube(rng: np.random.Generator) -> VirtualTube:
    """A tube entering anywhere in the arena's left part, sometimes bent, narrowing after a wide part."""
    half = float(rng.uniform(0.3, 0.7))
    wide = float(rng.uniform(0.4, 1.4))
    parts = (WidthPart('constant', wide), WidthPart('linear', 0.4, 0.2, 0.05))
    length = wide + 0.4 + float(rng.uniform(0.1, 0.5))
    pieces = (
        (ArcPiece(0.5 * length), ArcPiece(0.5 * length, 1.2, bool(rng.uniform() < 0.5)))
        if rng.uniform() < 0.6
        else (ArcPiece(length),)
    )
    center = ArcPath(pieces, (float(rng.uniform(-1.45, -0.6)), float(rng.uniform(-0.3, 0.3))), 0.0)
    return VirtualTube(center, WidthProfile(half, (*parts, WidthPart('constant', length - wide - 0.4))))


def test_every_packing_found_keeps_the_rules_and_the_bound() -> None:
    """Random tubes and N up to Oler's bound: whatever the search finds keeps the spacing, the box, the walls and
    the narrowing; it finds at least the robots of a single row across the entrance where the region has one."""
    rng = np.random.default_rng(7)
    found = 0
    for _ in range(12):
        t = random_tube(rng)
        bound = packing_bound(t)
        for n in sorted({2, max(bound - 3, 2)}):
            poses = packed_poses(t, n)
            if poses is not None:
                found += 1
                assert n <= bound
                assert_in_the_start_region(t, poses)
    assert found >= 12


def test_a_refusal_above_the_bound_is_said_physical() -> None:
    """bend35 at N = 15 (bound 12): the refusal says no layout holds them; at N = 12 (within the bound, no packing
    found) it says it is not shown to be physical, unless the proof is asked for (the sweep's,
    `robotarium_exp.packing_proof`)."""
    path = SWEEP_TUBES / 'bend35.toml'
    above = robotarium_fit(load_scene(path, n_robots=15))
    assert not above.fits and f'physically: at most {packing_bound(load_scene(path).tube)} robots' in above.reason
    within = robotarium_fit(load_scene(path, n_robots=12))
    assert not within.fits and 'physically' not in within.reason
    said = "not shown to be physical: Oler's bound lets up to 12 robots fit 0.4 m apart in the start region)"
    assert said in within.reason  # the proof not asked for, not said
