"""The derived Robotarium experiment: start formation, first narrowing, parking slots and formation density, checked
against their geometric definitions on the shipped tubes and on tubes built here."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from robotarium_exp.design import (
    QUEUE_BEFORE_NARROWING_M,
    WALL_CLEARANCE_M,
    Formation,
    Narrowing,
    entry_queue,
    first_inside_box,
    first_narrowing,
    formation_density,
    order_for_v2_initializer,
    staggered_rows,
    start_formation,
)
from robotarium_exp.parking_slots import (
    PARKING_DEPTH_M,
    PARKING_LANES_MAX,
    PARKING_NEAREST_M,
    PARKING_SPACING_M,
    PARKING_WALL_M,
    parking,
    parking_bound,
    slots_in_lanes,
)
from robotarium_exp.scene import load_scene
from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile

SPACING = ROBOTARIUM.ic_spacing_m
BOX = np.array(ROBOTARIUM.ic_box_m)


def tube(
    pieces: tuple[ArcPiece, ...],
    start: tuple[float, float],
    heading_deg: float,
    width: float | tuple[float, tuple[WidthPart, ...]],
) -> VirtualTube:
    """A tube of lines and arcs; ``width`` is a constant half-width or (start, parts) of a profile."""
    center = ArcPath(pieces, start, math.radians(heading_deg))
    if isinstance(width, float):
        profile = WidthProfile(width, (WidthPart('constant', center.length_m),))
    else:
        start_m, parts = width
        profile = WidthProfile(
            start_m, (*parts, WidthPart('constant', center.length_m - sum(p.length_m for p in parts)))
        )
    return VirtualTube(center, profile)


def straight(half_width_m: float, length_m: float = 2.45, start: tuple[float, float] = (-1.45, 0.0)) -> VirtualTube:
    return tube((ArcPiece(length_m),), start, 0.0, half_width_m)


TUBES = {
    'trapezoid': load_scene('robotarium_trapezoid').tube,
    'curve': load_scene('robotarium_curve').tube,
    'straight': straight(0.5),
    'wide': straight(0.75),  # four abreast
    'single_file': straight(0.15),  # one abreast
    'bend_left': tube((ArcPiece(0.6), ArcPiece(1.25, 1.2), ArcPiece(0.5)), (-1.3, -0.7), 0.0, 0.45),
    'right_to_left': tube((ArcPiece(0.6), ArcPiece(0.6, 1.5), ArcPiece(0.8)), (1.3, 0.3), 180.0, 0.4),
    'narrowing_in_bend': tube(
        (ArcPiece(0.8), ArcPiece(1.0, 1.0), ArcPiece(0.6)),
        (-1.3, -0.6),
        0.0,
        (0.5, (WidthPart('constant', 1.0), WidthPart('smooth', 0.5, 0.25))),
    ),
}
SWEEP = range(1, ROBOTARIUM.max_robots + 1)


@pytest.fixture(scope='module')
def formations() -> dict[tuple[str, int], Formation]:
    """Every constructed tube's formation for N = 1..20, built once."""
    return {(name, n): start_formation(t, n) for name, t in TUBES.items() for n in SWEEP}


def gaps(points: np.ndarray) -> np.ndarray:
    n = points.shape[1]
    return np.hypot(*(points[:2, :, None] - points[:2, None, :]))[np.triu_indices(n, 1)]


def box_holds(t: VirtualTube, l_from: float, l_to: float) -> bool:
    """Every cross-section of the tube between the two arc lengths lies inside the initialization box."""
    left, right = t.boundaries(np.linspace(l_from, l_to, 200))
    return bool(np.all(np.abs(left) <= BOX) and np.all(np.abs(right) <= BOX))


@pytest.mark.parametrize('name', sorted(TUBES))
def test_the_formation_keeps_the_spacing_the_walls_and_the_tube_direction(name: str, formations) -> None:
    t = TUBES[name]
    for n in SWEEP:
        f = formations[name, n]
        assert f.problem is None and f.poses.shape == (3, n), (name, n)
        assert n == 1 or gaps(f.poses).min() >= SPACING - 1e-12, (name, n)
        where = t.project(f.poses[:2])
        np.testing.assert_allclose([where.l_m.min(), where.l_m.max()], [f.l_back_m, f.l_front_m], atol=1e-9)
        # every robot faces along the tube where it stands
        tangent = t.tangent(where.l_m)
        heading = np.arctan2(tangent[:, 1], tangent[:, 0])
        np.testing.assert_allclose(np.angle(np.exp(1j * (f.poses[2] - heading))), 0.0, atol=1e-9)
        if f.queue or f.packed:  # moved back to end before the narrowing (test_entry_queue_*), or test_packing
            continue
        # the back row lies at the first cross-section inside the box, 0.1 m from the walls
        back = np.isclose(where.l_m, f.l_back_m, atol=1e-9)
        assert np.all(np.abs(where.y_m[back]) <= t.half_width(f.l_back_m) - WALL_CLEARANCE_M + 1e-9), (name, n)
        first = f.l_back_m - 0.02  # the first sampled cross-section inside the box (the entrance, or one further in)
        assert box_holds(t, first, first) and (first == 0.0 or not box_holds(t, first - 0.004, first - 0.004))
        narrowing = first_narrowing(t)
        if f.l_front_m <= (t.length_m if narrowing is None else narrowing.start_m):  # every row 0.1 m from the walls
            assert np.all(np.abs(where.y_m) <= t.half_width(where.l_m) - WALL_CLEARANCE_M + 1e-9), (name, n)
        if box_holds(t, f.l_back_m, f.l_front_m):  # the cross-sections it stands on are in the box: so is it
            assert np.all(np.abs(f.poses[:2].T) <= BOX), (name, n)


@pytest.mark.parametrize('name', sorted(TUBES))
def test_rows_and_columns_fill_the_entrance(name: str, formations) -> None:
    t = TUBES[name]
    for n in SWEEP:
        f = formations[name, n]
        if f.staggered or f.packed:  # test_staggered_rows_*, test_packing
            continue
        room = t.half_width(f.l_back_m) - WALL_CLEARANCE_M  # from the centre line to a robot's furthest place
        assert f.rows == math.ceil(n / f.columns) and f.columns <= n
        assert 0.5 * SPACING * (f.columns - 1) <= room + 1e-12  # the widest row fits between the walls ...
        assert f.columns == n or 0.5 * SPACING * f.columns > room  # ... and one robot more would not
        where = t.project(f.poses[:2])
        rows = np.unique(np.round(where.l_m, 6))
        assert rows.size == f.rows, (name, n)
        full = np.isclose(where.l_m, f.l_front_m, atol=1e-6).sum()
        assert full == f.columns  # the front row is full, the back row holds the rest
        assert np.isclose(where.l_m, f.l_back_m, atol=1e-6).sum() == n - (f.rows - 1) * f.columns or f.rows == 1
        if name in ('straight', 'wide', 'single_file', 'trapezoid'):  # straight: rows exactly the spacing apart
            assert f.length_m == pytest.approx(SPACING * (f.rows - 1), abs=1e-12)


@pytest.mark.parametrize('name', sorted(TUBES))
def test_staggered_rows_are_taken_only_where_plain_rows_reach_the_narrowing_and_end_sooner(
    name: str, formations
) -> None:
    """Rows alternate the widest row (its outer robots at the walls' clearance) and one robot fewer in its gaps, the
    front row the widest; taken only where the plain rows would reach into the narrowing, and then ending before
    it."""
    t = TUBES[name]
    narrowing = first_narrowing(t)
    for n in SWEEP:
        f = formations[name, n]
        if not f.staggered:
            continue
        assert narrowing is not None and f.l_front_m <= narrowing.start_m, (name, n)
        where = t.project(f.poses[:2])
        row_of = np.unique(np.round(where.l_m, 6), return_inverse=True)[1]
        sizes = np.bincount(row_of)[::-1]  # front row first
        wide = int(sizes[0])
        assert wide == f.columns >= 2 and np.all(sizes[1::2] <= wide - 1) and np.all(sizes[2::2] <= wide), (name, n)
        front = np.abs(where.y_m[row_of == row_of.max()])
        assert front.max() == pytest.approx(t.half_width(f.l_front_m) - WALL_CLEARANCE_M, abs=1e-9), (name, n)


def test_staggered_rows_on_a_strip_are_the_analytic_packing() -> None:
    """0.7 m of room (a tube 0.9 m wide): two at the clearances and one on the axis, 0.2 m apart (three robots per
    0.4 m where plain rows hold two); 0.8 m: also rows of three 0.4 m apart with two between at sqrt(0.4^2 - 0.2^2)."""
    ((lateral, pitch),) = staggered_rows(0.7, 5)
    assert pitch == pytest.approx(0.5 * SPACING)
    assert [row.tolist() for row in lateral] == [[-0.35, 0.35], [0.0], [-0.35, 0.35]]
    assert staggered_rows(0.7, 2) == []  # one row: nothing to stagger
    two, three = staggered_rows(0.8, 8)
    assert two[1] == pytest.approx(0.5 * SPACING) and three[1] == pytest.approx(math.sqrt(SPACING**2 - 0.2**2))
    assert [row.size for row in three[0]] == [3, 2, 3]
    np.testing.assert_allclose(three[0][1], [-0.2, 0.2])


def test_a_straight_tube_too_short_for_plain_rows_starts_staggered() -> None:
    """A 0.9 m wide straight tube narrowing at l = 1.0 m: eight robots in plain rows of two reach l = 1.22 m; staggered
    (2, 1, 2, 1, 2) they end at 0.02 + 4 x 0.2 m, every pair 0.4 m apart or more."""
    t = tube((ArcPiece(2.45),), (-1.45, 0.0), 0.0, (0.45, (WidthPart('constant', 1.0), WidthPart('smooth', 0.5, 0.3))))
    f = start_formation(t, 8)
    assert f.staggered and f.rows == 5 and f.columns == 2
    assert f.l_front_m - f.l_back_m == pytest.approx(4 * 0.5 * SPACING, abs=1e-9)
    assert gaps(f.poses).min() >= SPACING - 1e-12
    assert start_formation(TUBES['curve'], 10).staggered  # the shipped curve's ten: rows of 3 and 2 on its bend


def test_the_column_count_follows_the_entrance_width(formations) -> None:
    assert {name: formations[name, 20].columns for name in ('straight', 'wide', 'single_file')} == {
        'straight': 3,
        'wide': 4,
        'single_file': 1,
    }


@pytest.mark.parametrize('name', sorted(TUBES))
def test_robot_zero_is_least_crowded_and_robot_one_apart_from_it(name: str, formations) -> None:
    """Robot 0 at a slot with the fewest neighbours; robot 1 more than 0.55 m from it wherever a slot is, and
    no slot both farther and less crowded (or as crowded and ahead) than robot 1's passed over."""
    for n in range(3, 21):
        ic = formations[name, n].poses
        d = np.hypot(*(ic[:2, :, None] - ic[:2, None, :]))
        neighbours = (d < 1.25 * SPACING).sum(axis=0) - 1
        assert neighbours[0] == neighbours.min(), (name, n)
        if d[0].max() > 0.55:
            assert d[0, 1] > 0.55, (name, n)
            calmer = [k for k in range(2, n) if d[0, k] > 0.55 and neighbours[k] < neighbours[1]]
            assert not calmer, (name, n, calmer)
        else:
            assert d[0, 1] == d[0].max(), (name, n)


def test_robot_one_leaves_a_neighbouring_calm_slot_for_one_apart() -> None:
    """A 2 x 2 grid (0.4 m): robot 0 the front left; the front right is its neighbour (0.4 m), so robot 1 takes
    the diagonal (0.57 m), the rule's reason to exist (s_curve, N = 4)."""
    grid = np.array([[0.0, 0.0, -0.4, -0.4], [0.2, -0.2, 0.2, -0.2], [0.0] * 4])
    order = order_for_v2_initializer(grid)
    assert order[:2] == [0, 3] and sorted(order) == [0, 1, 2, 3]
    pair = np.array([[0.0, -0.4], [0.0, 0.0], [0.0, 0.0]])
    assert order_for_v2_initializer(pair) == [0, 1]  # none apart: the farthest, the only other


def test_the_order_puts_the_front_corners_first_and_keeps_every_robot() -> None:
    # a 3 x 3 grid heading +x, front row at x = 0: corners have 2 neighbours, edges 3, the centre 4
    x, y = np.meshgrid([0.0, -0.4, -0.8], [-0.4, 0.0, 0.4], indexing='ij')
    grid = np.array([x.ravel(), y.ravel(), np.zeros(9)])
    order = order_for_v2_initializer(grid)
    assert sorted(order) == list(range(9)) and order[:2] == [0, 2]  # the front corners, lower index first
    flipped = grid[:, ::-1].copy()  # the same slots listed back row first
    assert set(order_for_v2_initializer(flipped)[:2]) == {6, 8}
    assert order_for_v2_initializer(grid[:, :2]) == [0, 1]


def test_no_formation_without_a_section_in_the_box_or_room_between_the_walls() -> None:
    beyond = start_formation(straight(0.1, 3.0, (-1.5, 0.9)), 4)  # hugging the arena's top edge, |y| > 0.875
    assert beyond.problem is not None and 'no cross-section of the tube lies inside the box' in beyond.problem
    assert beyond.poses.shape == (3, 4) and np.isnan(beyond.poses).all() and (beyond.rows, beyond.columns) == (0, 0)
    tight = start_formation(straight(0.08), 2)
    assert tight.problem is not None and 'too narrow for a robot 0.1 m from each wall' in tight.problem


def width_tube(start_m: float, *parts: WidthPart) -> VirtualTube:
    length = sum(p.length_m for p in parts)
    return VirtualTube(ArcPath((ArcPiece(length),)), WidthProfile(start_m, parts))


@pytest.mark.parametrize(
    ('t', 'expected'),
    [
        (width_tube(0.5, WidthPart('constant', 3.0)), None),
        (width_tube(0.3, WidthPart('constant', 1.0), WidthPart('linear', 0.5, 0.6), WidthPart('constant', 1.0)), None),
        (
            width_tube(
                0.5, WidthPart('constant', 1.4), WidthPart('linear', 0.5, 0.25, 0.06), WidthPart('constant', 0.55)
            ),
            Narrowing(1.4, 1.9, 0.5, 0.25),
        ),
        (width_tube(0.6, WidthPart('smooth', 0.8, 0.2), WidthPart('constant', 1.0)), Narrowing(0.0, 0.8, 0.6, 0.2)),
        (  # widens, holds, then narrows twice: the first narrowing counts
            width_tube(
                0.3,
                WidthPart('smooth', 0.4, 0.6),
                WidthPart('constant', 0.5),
                WidthPart('linear', 0.6, 0.35),
                WidthPart('constant', 0.3),
                WidthPart('smooth', 0.2, 0.2),
            ),
            Narrowing(0.9, 1.5, 0.6, 0.35),
        ),
    ],
    ids=['constant', 'widening', 'linear', 'smooth_first', 'after_widening'],
)
def test_first_narrowing_on_analytic_profiles(t: VirtualTube, expected: Narrowing | None) -> None:
    found = first_narrowing(t)
    assert found == (None if expected is None else pytest.approx(expected))
    if found is not None:
        assert expected is not None and found.length_m == pytest.approx(expected.length_m)
        # the tube's own half-width: flat or widening before, falling inside, the after value at the end
        before = np.linspace(0.0, found.start_m, 50)
        assert np.all(np.diff(t.half_width(before)) >= -1e-12)
        assert t.half_width(found.start_m) == pytest.approx(found.half_width_before_m)
        assert t.half_width(found.end_m) == pytest.approx(found.half_width_after_m)
        assert t.half_width_slope(0.5 * (found.start_m + found.end_m)) < 0.0


def test_the_shipped_tubes_narrow_where_their_files_say() -> None:
    """Both files: half-width 0.5 m for 1.4 m, then to 0.25 m over 0.5 m."""
    for name in ('trapezoid', 'curve'):
        assert first_narrowing(TUBES[name]) == pytest.approx(Narrowing(1.4, 1.9, 0.5, 0.25))


WALL_TOLERANCE_M = 1e-3
"""A slot a millimetre inside the wall (room to turn into it) keeps it: a nearly square exit must not cost a lane
(the curve's exit tangent is 1.6e-3 rad off +x, which moves a lane 0.3 m aside 0.5 mm along x)."""


def keeps_the_wall(slots: np.ndarray) -> bool:
    return not ROBOTARIUM.outside_arena(slots, PARKING_WALL_M - WALL_TOLERANCE_M).any()


def scanned_layout(t: VirtualTube, n: int) -> tuple[int, float] | None:
    """The most lanes, and the deepest farthest row (at most 1 m beyond the exit, the nearest row at least
    0.08 m beyond it), that keep the wall, found by scanning depths every 0.5 mm; None when no layout does."""
    end, tangent = t.center_at(t.length_m), t.tangent(t.length_m)
    for lanes in range(min(n, PARKING_LANES_MAX), 0, -1):
        behind = PARKING_SPACING_M * ((n - 1) // lanes)
        depths = np.arange(PARKING_DEPTH_M, PARKING_NEAREST_M + behind - 1e-9, -5e-4)
        slots = slots_in_lanes(end, tangent, n, lanes, depths[:, None, None])  # (depths, 2, N): every depth at once
        outside = ROBOTARIUM.outside_arena(np.moveaxis(slots, 1, 0), PARKING_WALL_M).any(axis=-1)
        if not outside.all():
            return lanes, float(depths[np.argmin(outside)])
    return None


@functools.cache
def staggered_capacity(t: VirtualTube, wall_m: float) -> int:
    """The most slots staggered rows hold, every slot ``wall_m`` from the arena's edge: the farthest row at the
    deepest depth a slot can have (scanned every 0.5 mm) or 1 cm, 2 cm, ... up to 0.3 m less, R rows evenly from
    there to 0.08 m beyond the exit, lanes the least pitch apart that keeps 0.3 m to the next row, odd rows half a
    pitch across; every shift of the lanes across scanned every 2 mm."""
    end, tangent = t.center_at(t.length_m), t.tangent(t.length_m)
    normal = np.array([-tangent[1], tangent[0]])
    across = np.arange(-4.0, 4.0, 1e-3)  # the arena's diagonal is 3.8 m

    def holds(depth: float, offsets: np.ndarray) -> np.ndarray:
        points = (end + depth * tangent)[:, None, None] + normal[:, None, None] * offsets[None]
        return ~ROBOTARIUM.outside_arena(points, wall_m)

    depths = np.arange(PARKING_DEPTH_M, PARKING_NEAREST_M - 1e-9, -5e-4)
    inside = [holds(d, across[None, :]).any() for d in depths]
    if not any(inside):
        return 0
    deepest, best = float(depths[int(np.argmax(inside))]), 0
    for far in deepest - np.arange(0.0, 0.3 + 1e-9, 0.01):
        for rows in range(2, 9) if far > PARKING_NEAREST_M else ():
            step = min(PARKING_SPACING_M, (far - PARKING_NEAREST_M) / (rows - 1))
            if rows > 2 and 2 * step < PARKING_SPACING_M:
                break
            pitch = max(PARKING_SPACING_M, 2 * math.sqrt(max(PARKING_SPACING_M**2 - step**2, 0.0))) + 1e-9
            shifts = np.arange(0.0, pitch, 2e-3)[:, None]
            lanes = np.arange(-14, 15)[None, :] * pitch  # 4 m either side
            counts = sum(holds(far - r * step, shifts + lanes + 0.5 * pitch * (r % 2)).sum(axis=1) for r in range(rows))
            best = max(best, int(np.max(counts)))
    return best


def scanned_moved_lanes(t: VirtualTube, n: int) -> int | None:
    """The most lanes that keep the wall with the nearest row at least 0.08 m beyond the exit when the lanes may
    also move across (along the exit's normal), by scanning moves and depths every 5 mm; None when none do."""
    end, tangent = t.center_at(t.length_m), t.tangent(t.length_m)
    normal = np.array([-tangent[1], tangent[0]])
    moves = np.arange(-2.0, 2.0, 5e-3)
    for lanes in range(min(n, PARKING_LANES_MAX), 0, -1):
        behind = PARKING_SPACING_M * ((n - 1) // lanes)
        depths = np.arange(PARKING_DEPTH_M, PARKING_NEAREST_M + behind - 1e-9, -5e-3)
        at_exit = slots_in_lanes(end, tangent, n, lanes, depths[:, None, None])  # (depths, 2, N)
        slots = at_exit[None] + moves[:, None, None, None] * normal[None, None, :, None]  # (moves, depths, 2, N)
        outside = ROBOTARIUM.outside_arena(np.moveaxis(slots, 2, 0), PARKING_WALL_M).any(axis=-1)
        if not outside.all():
            return lanes
    return None


def assert_parking_rules(slots: np.ndarray, t: VirtualTube) -> None:
    """0.3 m apart, the farthest first; the layout of the most lanes that keeps the wall with the farthest row
    deepest (at most 0.45 m, at least on the exit line), by an independent scan; when none does, lanes moved across
    as many as a scan of moves finds, keeping the wall and 0.08 m beyond the exit; when none do either, the slots do
    not keep the wall or lie too near the exit (the verdict refuses them)."""
    n = slots.shape[1]
    assert n == 1 or gaps(slots).min() >= PARKING_SPACING_M - 1e-12
    end, tangent = t.center_at(t.length_m), t.tangent(t.length_m)
    beyond = tangent @ (slots - end[:, None])
    assert np.all(np.diff(beyond) <= 1e-12)
    found = scanned_layout(t, n)
    if found is not None:
        lanes, depth = found
        assert keeps_the_wall(slots) and beyond[0] == pytest.approx(depth, abs=6e-4)
        np.testing.assert_allclose(slots, slots_in_lanes(end, tangent, n, lanes, beyond[0]), atol=1e-9)
        return
    moved = scanned_moved_lanes(t, n)
    if moved is None:  # staggered rows, or where none hold N the fallback the fit refuses
        kept = keeps_the_wall(slots) and beyond.min() >= PARKING_NEAREST_M - 1e-9
        if not kept:  # no staggered rows hold N, even 2 mm further from the edge (scans differ by a millimetre)
            assert n > staggered_capacity(t, PARKING_WALL_M + 2e-3)
            return
        assert n <= staggered_capacity(t, PARKING_WALL_M - 2e-3) and n <= parking_bound(t)
        rows = np.unique(np.round(beyond, 6))  # rows evenly apart
        assert rows.size >= 2 and np.ptp(np.diff(rows)) < 1e-5
        return
    assert keeps_the_wall(slots) and beyond.min() >= PARKING_NEAREST_M - 1e-9
    across = np.array([-tangent[1], tangent[0]]) @ (slots - end[:, None])
    assert np.unique(np.round(across, 6)).size == min(moved, n)  # as many lanes as the scan found


@pytest.mark.parametrize(
    'name',
    [
        'trapezoid',
        'curve',
        'bend_left',
        'right_to_left',
        'narrowing_in_bend',
    ],
)
def test_parking_slots_keep_the_wall_and_their_spacing(name: str) -> None:
    for n in SWEEP:
        slots = parking(TUBES[name], n)
        assert slots.shape == (2, n)
        assert_parking_rules(slots, TUBES[name])


def test_the_trapezoids_slots_are_six_lanes_the_wall_from_the_edge() -> None:
    """Exit (1, 0) facing +x, 0.6 m of arena beyond, 0.2 m of it the wall: rows at 1.4 and 1.1 m, six lanes 0.3 m
    apart across y = 0 (+-0.75 m, inside the arena's +-0.8 m less the wall)."""
    lanes = np.array([-0.75, -0.45, -0.15, 0.15, 0.45, 0.75])
    np.testing.assert_allclose(parking(TUBES['trapezoid'], 6), [[1.4] * 6, lanes], atol=1e-12)
    expected = np.array([[1.4] * 6 + [1.1], [*lanes, lanes[0]]])
    np.testing.assert_allclose(parking(TUBES['trapezoid'], 7), expected, atol=1e-12)


def test_parking_moves_in_where_the_arena_ends_sooner_and_narrows_near_a_side() -> None:
    short = straight(0.3, 2.7)  # exit at x = 1.25: 0.35 m of arena beyond, 0.2 m of it the wall
    slots = parking(short, 3)
    np.testing.assert_allclose(slots[0], 1.4, atol=1e-12)
    assert_parking_rules(slots, short)
    on_exit = straight(0.3, 2.85)  # exit at x = 1.4: all 0.2 m beyond it are the wall, the slots on the exit line
    np.testing.assert_allclose(parking(on_exit, 2)[0], 1.4, atol=1e-12)
    high = straight(0.2, 2.45, (-1.45, 0.4))  # exit at y = 0.4: five lanes (+-0.6) or four (+-0.45) pass y = 0.8
    slots = parking(high, 6)
    assert_parking_rules(slots, high)
    np.testing.assert_allclose(np.unique(slots[1]), 0.4 + np.array([-0.3, 0.0, 0.3]), atol=1e-12)


def test_parking_at_random_exits_keeps_every_rule_or_is_refused() -> None:
    """Property over 40 straight tubes ending anywhere in the arena, heading anywhere, N from 1 to 20: the slots
    keep 0.3 m between them always; where they also keep the wall and lie 0.08 m beyond the exit, there are no more
    of them than Oler's bound on the room beyond it allows, and the independent scans agree on which layout it is."""
    rng = np.random.default_rng(50)
    for _ in range(40):
        heading = rng.uniform(-180.0, 180.0)
        end = np.array([rng.uniform(-1.3, 1.3), rng.uniform(-0.7, 0.7)])
        direction = np.array([math.cos(math.radians(heading)), math.sin(math.radians(heading))])
        t = tube((ArcPiece(0.5),), tuple(end - 0.5 * direction), heading, 0.2)
        assert_parking_rules(parking(t, int(rng.integers(1, 21))), t)


def test_staggered_rows_park_where_lanes_cannot() -> None:
    """Exit (1.1, 0) facing +x: the room beyond is 0.22 m deep (1.18 to 1.4 m) and 1.6 m across, one row of six
    lanes. Two rows 0.22 m apart keep 0.3 m between neighbours when their lanes stand 2 sqrt(0.3^2 - 0.22^2) =
    0.408 m apart, the second row shifted half of that: four in each (0.204 + 3 x 0.408 = 1.43 <= 1.6), eight in
    all; nine are not parked (Oler's bound on the room: floor(11.58) = 11)."""
    gate = straight(0.3, 2.55)
    eight = parking(gate, 8)
    assert_parking_rules(eight, gate)
    np.testing.assert_allclose(np.unique(np.round(eight[0], 3)), [1.18, 1.4], atol=1.5e-3)
    for row in (eight[1][eight[0] > 1.3], eight[1][eight[0] < 1.3]):
        np.testing.assert_allclose(np.diff(np.sort(row)), 2 * math.sqrt(0.3**2 - 0.22**2), atol=2e-3)
    assert gaps(eight).min() >= PARKING_SPACING_M
    nine = parking(gate, 9)
    assert not keeps_the_wall(nine) or (nine[0] - 1.1).min() < PARKING_NEAREST_M
    assert parking_bound(gate) == 11


def test_when_no_slots_fit_the_widest_are_returned_for_the_verdict_to_refuse() -> None:
    edge = straight(0.02, 3.0, (-1.45, 0.0))  # exit at x = 1.55: no slot 0.08 m beyond it keeps the wall
    slots = parking(edge, 7)
    assert scanned_layout(edge, 7) is None and scanned_moved_lanes(edge, 7) is None
    beyond = np.array([1.0, 0.0]) @ (slots - edge.center_at(edge.length_m)[:, None])
    assert not keeps_the_wall(slots) or beyond.min() < PARKING_NEAREST_M


def test_lanes_move_across_only_where_none_fit_on_the_exit() -> None:
    """The shipped curve's exit lies at y = 0.3: six robots park in four lanes centred on it (as before), ten in six
    lanes moved to the arena's middle, which four centred lanes cannot hold (three rows: the nearest behind the
    exit)."""
    curve = TUBES['curve']
    six = parking(curve, 6)
    np.testing.assert_allclose(np.unique(np.round(six[1], 2)), 0.3 + np.array([-0.45, -0.15, 0.15, 0.45]), atol=2e-3)
    ten = parking(curve, 10)
    assert scanned_layout(curve, 10) is None and np.unique(np.round(ten[1], 2)).size == 6
    assert_parking_rules(ten, curve)


@pytest.mark.parametrize('name', ['straight', 'wide', 'single_file', 'trapezoid'])
def test_the_formation_density_is_n_over_its_padded_area(name: str, formations) -> None:
    """On a straight tube of half-width lambda: N / (2 lambda (span + 2 r_a)), while the padded span stays in the
    constant part."""
    t, r_a = TUBES[name], SPACING - 0.1
    lam = float(t.half_width(0.0))
    narrowing = first_narrowing(t)
    constant_to = t.length_m if narrowing is None else narrowing.start_m
    checked = 0
    for n in SWEEP:
        f = formations[name, n]
        if f.l_front_m + r_a > constant_to:
            continue
        expected = n / (2.0 * lam * (f.length_m + 2.0 * r_a))
        assert formation_density(t, f, r_a) == pytest.approx(expected, rel=1e-12), (name, n)
        checked += 1
    assert checked >= 3


def random_narrowing_tube(rng: np.random.Generator) -> VirtualTube:
    """A tube with a wide part and a narrowing, its entrance anywhere in the arena's left half, heading roughly
    along the arena, sometimes bent."""
    half = float(rng.uniform(0.25, 0.9))
    wide = float(rng.uniform(0.0, 1.2))
    parts = (WidthPart('constant', wide), WidthPart('linear', 0.4, 0.2, 0.05)) if wide > 0.0 else ()
    parts = parts or (WidthPart('linear', 0.4, 0.2, 0.05),)
    length = wide + 0.4 + float(rng.uniform(0.1, 0.6))
    start = (float(rng.uniform(-1.45, 0.2)), float(rng.uniform(-0.3, 0.3)))
    bend = rng.uniform() < 0.5
    pieces = (ArcPiece(0.5 * length), ArcPiece(0.5 * length, 1.5, True)) if bend else (ArcPiece(length),)
    return tube(pieces, start, float(rng.uniform(-20.0, 20.0)), (half, parts))


def test_entry_queue_properties_over_random_starts() -> None:
    """Every queue the design returns: robots at least the spacing apart, all in the initializer's box, the back row
    as far back as the box allows, the ones behind the entrance between the wall lines continued behind it (outside
    the tube, never beside a wall), the others 0.1 m from the walls, the front row before the narrowing, and the rows
    a spacing apart in the order they enter."""
    rng = np.random.default_rng(50)
    queues = behind = 0
    for _ in range(300):
        t = random_narrowing_tube(rng)
        n = int(rng.integers(2, 21))
        q = entry_queue(t, n)
        if q is None:
            continue
        queues += 1
        narrowing = first_narrowing(t)
        assert narrowing is not None and q.queue and q.problem is None and q.poses.shape == (3, n)
        assert gaps(q.poses).min() >= SPACING - 1e-12
        assert np.all(np.abs(q.poses[:2].T) <= BOX)
        where = t.project(q.poses[:2])
        room = np.where(where.l_m < 0.0, t.half_width(0.0), t.half_width(np.maximum(where.l_m, 0.0)))
        assert np.all(np.abs(where.y_m) <= room - WALL_CLEARANCE_M + 1e-9)
        assert where.l_m.max() <= narrowing.start_m - QUEUE_BEFORE_NARROWING_M  # the swarm starts before it
        # the back row as far back as the box allows: a full row 2 cm further back leaves the box
        l_back = where.l_m.min() - 0.02
        row = t.center_at(l_back) + np.outer((np.arange(q.columns) - 0.5 * (q.columns - 1)) * SPACING, t.normal(l_back))
        assert np.any(np.abs(row) > BOX)
        rows = np.unique(np.round(where.l_m, 6))
        assert rows.size == q.rows and q.rows == math.ceil(n / q.columns)
        assert (
            q.rows == 1 or np.diff(rows).min() >= SPACING - 1e-9
        )  # rows a spacing apart: each enters after the one ahead
        behind += int(np.count_nonzero(where.l_m < 0.0))
    assert queues >= 30 and behind >= 100  # the random tubes exercise the queue behind the entrance


def test_entry_queue_only_where_the_box_has_room_and_the_tube_narrows() -> None:
    assert entry_queue(straight(0.5), 20) is None  # no narrowing: nothing to queue for
    shipped = load_scene('robotarium_trapezoid').tube  # enters at x = -1.45, outside the box: no room behind
    assert entry_queue(shipped, 15) is None and entry_queue(shipped, 20) is None
    assert start_formation(shipped, 20).queue is False  # the fit verdict refuses it, as before


@pytest.mark.parametrize('n', range(1, 13))
def test_a_formation_that_fits_is_unchanged(n: int) -> None:
    t = load_scene('robotarium_trapezoid').tube
    f = start_formation(t, n)
    assert not f.queue and f.l_back_m == first_inside_box(t)  # the first cross-section in the box, as before


@pytest.mark.parametrize('name', ['robotarium_trapezoid_20', 'robotarium_curve_20'])
def test_the_twenty_robot_scenes_queue_two_rows_behind_the_entrance(name: str) -> None:
    scene = load_scene(name)
    f = start_formation(scene.tube, 20)
    assert f.queue and (f.rows, f.columns) == (4, 5)
    where = scene.tube.project(f.poses[:2])
    assert np.count_nonzero(where.l_m < 0.0) == 10  # two rows of five outside the tube, behind its entrance
    assert np.all(np.abs(where.y_m[where.l_m < 0.0]) <= scene.tube.half_width(0.0) - WALL_CLEARANCE_M + 1e-9)
