"""A Robotarium experiment derived from its intent: the start formation and the swarm's values.

A Robotarium scene declares a tube and a number of robots (``[robotarium] n_robots``); everything the paper's
Robotarium scenes set by hand is derived here from the tube, N and `ROBOTARIUM`, each
value with its reason (``vtube scene show`` prints them):

- the start formation: rows across the tube ``ic_spacing_m`` (0.4 m) apart, as many columns as fit the entrance
  with `WALL_CLEARANCE_M` to each wall, the back row at the first cross-section inside the box the testbed
  initializes robots in, robots 0 and 1 where V2's initializer cannot leave them stuck; where those rows reach the
  first narrowing, the entry queue behind the entrance, staggered rows, or a packing in no rows
  (`robotarium_exp.packing`);
- r_s (the law's barrier keeps 2 r_s, the safety filter's distance) and r_a = spacing - r_s, so that the formation
  rests at the edge of the interaction band, r_s + r_a = the spacing: not compressed, not loose;
- rho0 = rho_d: the formation's density under the package's measure, so the swarm starts on its plan and cruises
  in the formation it starts in; rho_max = 1 / (2 pi r_s^2) (the formula that reproduces Table 1's value);
- the look-ahead (`look_ahead`): the first narrowing's length plus the formation's length plus two
  interaction bands, so that the density change (p7) asks for before the narrowing is one the rows can make (the
  fit verdict checks that the formation starts before the narrowing);
(the parking slots beyond the exit are `robotarium_exp.parking_slots`').

Whether the result fits the testbed is `robotarium_exp.fit`'s one verdict; nothing here refuses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.packing import QUEUE_BEFORE_NARROWING_M, QUEUE_BEHIND_M, WALL_CLEARANCE_M, packed_poses
from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import Narrowing
from vtube_planning.geometry.width import first_narrowing as narrowing_of
from vtube_planning.onboard.density import swarm_density

FloatArray = NDArray[np.float64]

R_S_M = 0.10
"""r_s: the law's barrier keeps 2 r_s = 0.2 m between control points, as much as the safety filter does."""
INITIALIZER_APART_M = 0.55
"""Robots 0 and 1 start more than this far apart: every traced stall of V2's initializer had their slots 0.40-0.50
m apart (``docs/robotarium.md`` §2.6); the diagonal of a 2 x 2 grid at the spacing (0.57 m) is just beyond."""


@dataclass(frozen=True)
class Formation:
    """The start formation: poses (3, N) in robot order, its rows and columns (the widest row), the arc lengths of
    its back and front rows, why it could not be built (None: it could), whether it is the entry queue
    (`entry_queue`), whether its rows are staggered (`staggered_rows`) and whether it is packed in no rows
    (`robotarium_exp.packing.packed_poses`: each robot counts as a row of one)."""

    poses: FloatArray
    rows: int
    columns: int
    l_back_m: float
    l_front_m: float
    problem: str | None = None
    queue: bool = False
    staggered: bool = False
    packed: bool = False

    @property
    def length_m(self) -> float:
        """From the back row to the front row, along the tube."""
        return self.l_front_m - self.l_back_m


def first_narrowing(tube: VirtualTube) -> Narrowing | None:
    """The tube's first narrowing, from its width's knots (`vtube_planning.geometry.width.first_narrowing`), or None
    for a tube that never narrows."""
    return narrowing_of(*tube.width.knots)


LOOK_AHEAD_BANDS = 2
"""Interaction bands (the spacing) in the look-ahead beyond the narrowing and the formation (`look_ahead`)."""
LOOK_AHEAD_STEP_M = 0.05
"""The look-ahead is rounded to this: a bend that spreads the formation by a centimetre does not move it."""


def look_ahead(narrowing_m: float, formation_m: float) -> float:
    """The plan's look-ahead for a narrowing ``narrowing_m`` long (0: none) and a formation ``formation_m`` long
    (back row to front row): the narrowing plus the formation plus `LOOK_AHEAD_BANDS` interaction bands (the
    spacing), to `LOOK_AHEAD_STEP_M`. The longer the look-ahead, the gentler the density change (p7) asks
    for before the narrowing, and a swarm in rows of the tube's width can only lengthen to thin out. *Measured*
    with ``vtube robotarium run --no-initialization`` (the dip's mean density error), without the two bands against
    with them: the trapezoid at N = 6, 7 % (0.9 m) against 4 % (1.7 m; 38.1 s to pass instead of 41.6 s); the wide
    sweep tube at N = 6, 45 % against 6 %; the trapezoid at N = 10, 30 % against 19 %."""
    span = narrowing_m + formation_m + LOOK_AHEAD_BANDS * ROBOTARIUM.ic_spacing_m
    return round(round(span / LOOK_AHEAD_STEP_M) * LOOK_AHEAD_STEP_M, 3)


def start_formation(tube: VirtualTube, n_robots: int) -> Formation:
    """Rows across the tube, headings along it, every pair at least the spec's spacing apart.

    Rows and columns start ``ROBOTARIUM.ic_spacing_m`` apart along and across the tube; on a bend the inner side
    converges, so the row spacing grows (by 2 % steps) until every pair keeps it. The back row stands at the first
    cross-section inside the box. When the rows would then reach into the first narrowing, the formation is the entry
    queue (`entry_queue`) where the box has room behind the entrance, else staggered rows (`staggered_rows`) where
    they end before it, else the staggered queue, else a packing in no rows (`robotarium_exp.packing`); what is
    left is the plain rows, for the fit verdict to refuse.
    """
    l_back = first_inside_box(tube)
    narrowing = first_narrowing(tube)
    rows: Formation | None = None
    for staggered in (False, True):
        if l_back is not None:
            room = 2.0 * (float(tube.half_width(l_back)) - WALL_CLEARANCE_M)
            if room < 0.0:
                why = f'the entrance is too narrow for a robot {WALL_CLEARANCE_M} m from each wall'
                return _no_formation(n_robots, why)
            formation = _rows(tube, n_robots, room, l_back, staggered)
            rows = rows or formation
            if formation.rows and (narrowing is None or formation.l_front_m <= narrowing.start_m):
                return formation
        queue = entry_queue(tube, n_robots, staggered)
        if queue is not None:
            return queue
    packed = packed_poses(tube, n_robots) if rows is not None else None
    if packed is not None:
        l_m = tube.project(packed[:2]).l_m
        ordered: FloatArray = packed[:, order_for_v2_initializer(packed)]
        return Formation(ordered, n_robots, 1, float(l_m.min()), float(l_m.max()), packed=True)
    return rows or _no_formation(
        n_robots, 'no cross-section of the tube lies inside the box the testbed initializes robots in'
    )


def _rows(tube: VirtualTube, n_robots: int, room: float, l_back: float, staggered: bool) -> Formation:
    """The formation across ``room`` (m, between the wall clearances) whose back row stands at ``l_back``, ordered for
    V2's initializer: plain rows, or the staggered rows (`staggered_rows`) that end soonest (an empty formation, no
    rows, where there are none)."""
    spacing = ROBOTARIUM.ic_spacing_m
    if staggered:
        layouts = [
            (lateral, *_placed(tube, lateral, l_back, pitch)) for lateral, pitch in staggered_rows(room, n_robots)
        ]
        if not layouts:
            return Formation(np.zeros((3, 0)), 0, 0, l_back, l_back)
        lateral, poses, l_front = min(layouts, key=lambda layout: layout[2])
    else:
        columns = min(n_robots, math.floor(room / spacing + 1e-9) + 1)  # 0.4 / 0.4 is 0.99999...
        sizes = [min(columns, n_robots - first) for first in range(0, n_robots, columns)]
        lateral = [np.asarray((np.arange(size) - 0.5 * (size - 1)) * spacing, dtype=float) for size in sizes]
        for row_spacing in spacing * (1.0 + 0.02 * np.arange(50)):
            poses = _grid(tube, lateral, np.full(len(lateral), l_back) + row_spacing * np.arange(len(lateral))[::-1])
            gaps = np.hypot(*(poses[:2, :, None] - poses[:2, None, :]))[np.triu_indices(n_robots, 1)]
            if gaps.size == 0 or gaps.min() >= spacing - 1e-12:
                break
        l_front = l_back + float(row_spacing) * (len(lateral) - 1)
    ordered: FloatArray = poses[:, order_for_v2_initializer(poses)]
    return Formation(ordered, len(lateral), max(row.size for row in lateral), l_back, l_front, staggered=staggered)


def staggered_rows(room: float, n_robots: int) -> list[tuple[list[FloatArray], float]]:
    """Staggered rows across ``room``: for each c from 2 to the plain rows' columns, rows alternating c robots spread
    over the whole room and c - 1 in their gaps, at the least pitch that keeps the spacing between neighbouring
    rows on a straight tube; each as lateral offsets per row (front first, the back row the offsets of its kind
    nearest the axis) and that pitch; none for a single row.

    A tube 0.9 m wide (room 0.7 m) holds plain rows of two, 0.4 m apart (5 robots a metre), and staggered rows of two
    at the walls' clearance and one on the axis 0.2 m apart (7.5 a metre: Oler's bound on a 0.7 m strip is 7.55); a
    tube 1.0 m wide, plain rows of three (7.5 a metre) or rows of three 0.4 m apart and two between, 0.35 m apart
    (7.2 a metre), which still end sooner on a short stretch (eight robots in 0.69 m instead of 0.8 m).
    """
    spacing = ROBOTARIUM.ic_spacing_m
    layouts = []
    for wide in range(2, min(math.floor(room / spacing + 1e-9) + 1, n_robots - 1) + 1):
        gap = room / (wide - 1)
        pitch = max(math.sqrt(max(spacing**2 - 0.25 * gap**2, 0.0)), 0.5 * spacing)
        kinds = [(np.arange(wide) - 0.5 * (wide - 1)) * gap, (np.arange(wide - 1) - 0.5 * (wide - 2)) * gap]
        lateral: list[FloatArray] = []
        placed = 0
        while placed < n_robots:
            kind = kinds[len(lateral) % 2]
            take = min(kind.size, n_robots - placed)
            lateral.append(np.sort(kind[np.argsort(np.abs(kind), kind='stable')[:take]]))
            placed += take
        layouts.append((lateral, pitch))
    return layouts


PLACE_STEP = 0.01
"""A staggered row moves forward by this share of the pitch until it keeps the spacing (`_placed`)."""


def _placed(tube: VirtualTube, lateral: list[FloatArray], l_back: float, pitch: float) -> tuple[FloatArray, float]:
    """Rows at ``lateral`` offsets (front first) placed from the back row at ``l_back`` forwards, each the least
    multiple of `PLACE_STEP` pitch beyond ``pitch`` from the one behind it that keeps the spacing to every robot placed
    (on a bend only the rows on it move apart): the poses and the front row's arc length."""
    spacing = ROBOTARIUM.ic_spacing_m
    l_rows = [l_back]
    for row in range(len(lateral) - 2, -1, -1):
        behind = _grid(tube, lateral[row + 1 :], np.array(l_rows[::-1]))
        l_k = l_rows[-1] + pitch
        while (
            np.hypot(*(_grid(tube, [lateral[row]], np.array([l_k]))[:2, :, None] - behind[:2, None, :])).min()
            < spacing - 1e-12
        ):
            l_k += PLACE_STEP * pitch
        l_rows.append(l_k)
    return _grid(tube, lateral, np.array(l_rows[::-1])), l_rows[-1]


QUEUE_BOX_MARGIN_M = 0.01
"""The queue's back row stands this far inside the box (past the first sampled arc length whose row is inside)."""


def entry_queue(tube: VirtualTube, n_robots: int, staggered: bool = False) -> Formation | None:
    """The entry phase's start: the formation's back row at the first arc length, behind the entrance too, where a
    row of it stands inside the box the testbed initializes robots in; the rows behind l = 0 queue on the tube's
    straight extension (``docs/theory.md`` §12). None when the tube does not narrow, or the front row would reach
    the narrowing (within `QUEUE_BEFORE_NARROWING_M`).

    Columns are the entrance's (`WALL_CLEARANCE_M` to each wall line), so every robot of the queue stands between
    the lines of the walls continued behind the entrance and enters through the entrance, row after row, never
    through a wall; the law's tube keeping holds it there (the extension keeps the entrance's width), and the
    safety filter's wall rows take over at l = 0. The back row stands as far back as the box allows, as the start
    formation's does, so that the swarm has the most room to thin out before the narrowing (*measured* with the
    front row placed at the narrowing instead, twenty robots' trapezoid at N = 10 and 12: the dip's density error
    37 % and 36 %, and 78 robot-steps with a body on a wall at N = 12). ``staggered``: in staggered rows
    (`staggered_rows`; None where they are not denser).
    """
    narrowing = first_narrowing(tube)
    room = 2.0 * (float(tube.half_width(0.0)) - WALL_CLEARANCE_M)
    if narrowing is None or room < 0.0:
        return None
    columns = min(n_robots, math.floor(room / ROBOTARIUM.ic_spacing_m + 1e-9) + 1)
    half_span = 0.5 * room if staggered else 0.5 * (columns - 1) * ROBOTARIUM.ic_spacing_m
    l_back = _first_row_in_box(tube, half_span, narrowing.start_m)
    if l_back is None:
        return None
    queue = _rows(tube, n_robots, room, l_back, staggered)
    if not queue.rows:
        return None
    inside = np.all(np.abs(queue.poses[:2].T) <= np.array(ROBOTARIUM.ic_box_m), axis=1)
    fits = bool(inside.all()) and queue.l_front_m <= narrowing.start_m - QUEUE_BEFORE_NARROWING_M
    return replace(queue, queue=True) if fits else None


def _first_row_in_box(tube: VirtualTube, half_span: float, l_end_m: float) -> float | None:
    """The smallest arc length from `QUEUE_BEHIND_M` behind the entrance to ``l_end_m`` at which a full row, its
    outer robots ``half_span`` off the axis, lies inside the box, plus `QUEUE_BOX_MARGIN_M`; None if there is none."""
    l_m = np.linspace(-QUEUE_BEHIND_M, l_end_m, 2001)
    across = np.array([-half_span, half_span])
    points = tube.center_at(l_m)[:, None, :] + across[None, :, None] * tube.normal(l_m)[:, None, :]
    inside = np.all(np.abs(points) <= np.array(ROBOTARIUM.ic_box_m), axis=(1, 2))
    return float(l_m[np.argmax(inside)]) + QUEUE_BOX_MARGIN_M if inside.any() else None


def _grid(tube: VirtualTube, lateral: list[FloatArray], l_rows: FloatArray) -> FloatArray:
    """Poses (3, n) of rows at arc lengths ``l_rows``, robots at their rows' ``lateral`` offsets, headings along the
    tube."""
    l_k = np.concatenate([np.full(y.size, l_row) for l_row, y in zip(l_rows, lateral, strict=True)])
    y = np.concatenate(lateral)
    points = tube.center_at(l_k) + y[:, None] * tube.normal(l_k)
    tangent = tube.tangent(l_k)
    grid: FloatArray = np.array([points[:, 0], points[:, 1], np.arctan2(tangent[:, 1], tangent[:, 0])])
    return grid


def _no_formation(n_robots: int, problem: str) -> Formation:
    return Formation(np.full((3, n_robots), np.nan), 0, 0, math.nan, math.nan, problem)


def first_inside_box(tube: VirtualTube) -> float | None:
    """Smallest arc length (plus 0.02 m) whose whole cross-section lies inside the initialization box, or None."""
    l_m = np.linspace(0.0, tube.length_m, 2001)
    left, right = tube.boundaries(l_m)
    box = np.array(ROBOTARIUM.ic_box_m)
    inside = np.all(np.abs(left) <= box, axis=1) & np.all(np.abs(right) <= box, axis=1)
    return float(l_m[np.argmax(inside)]) + 0.02 if inside.any() else None


def order_for_v2_initializer(ic: FloatArray) -> list[int]:
    """Robot order for V2's initializer: robot 0 the slot with the fewest neighbours (front first), robot 1 the
    first slot in that order more than `INITIALIZER_APART_M` from it (else the slot farthest from it).

    V2 chooses the robots it rescues from deadlocks with ``np.isin`` of their indices against the boolean "arrived"
    mask, so robot 0 is never rescued while any robot is on its way and robot 1 never once any has arrived
    (``docs/robotarium.md`` §2.6). Every traced stall had robots 0 and 1 within 0.5 m of each other: one stops in
    a gap next to the other, or their final turns bend each other's for good. *Measured*
    (``python -m benchmarks.initializer_stalls``): on the two formations at risk (``s_curve`` and ``bend35``, N = 4)
    the former rule (the two least crowded slots, 0.40-0.50 m apart there) stalled 2 of 300 initializations, this
    one 0 of 300; on the trapezoid's formation, robots 0 and 1 at the front corners (0.8 m apart, which both rules
    choose), 0 of 500.
    """
    n = ic.shape[1]
    neighbours = neighbour_counts(ic)
    ahead = ic[0] * np.cos(ic[2]) + ic[1] * np.sin(ic[2])  # how far along its heading: the front row first
    ranked = sorted(range(n), key=lambda k: (neighbours[k], -round(float(ahead[k]), 6), k))
    if n < 2:
        return ranked
    gaps = np.hypot(*(ic[:2] - ic[:2, ranked[0], None]))
    apart = [k for k in ranked[1:] if gaps[k] > INITIALIZER_APART_M]
    first = [ranked[0], apart[0] if apart else int(np.argmax(gaps))]
    return first + [k for k in range(n) if k not in first]


def neighbour_counts(ic: FloatArray) -> NDArray[np.int_]:
    """How many other slots lie within 1.25 x the spacing of each slot."""
    gaps = np.hypot(*(ic[:2, :, None] - ic[:2, None, :]))
    counts: NDArray[np.int_] = np.asarray((gaps < 1.25 * ROBOTARIUM.ic_spacing_m).sum(axis=0) - 1)
    return counts


def formation_density(tube: VirtualTube, formation: Formation, r_a_m: float) -> float:
    """The formation's density under the package's measure, padded by r_a (robots/m^2)."""
    return swarm_density(tube, tube.project(formation.poses[:2]).l_m, r_a_m)
