"""The parking slots of a Robotarium experiment: where the robots past the exit stand until the run ends.

Lanes and rows `PARKING_SPACING_M` apart beyond the tube's exit, as many lanes and as deep as the arena allows,
centred on the exit or, where only that fits them in the arena, moved across it; where no lanes hold the swarm,
staggered rows nearer together, each shifted half a pitch from the next, every slot still the spacing from every
other (`parking`). How many robots the room beyond the exit holds at most, in any layout, is `parking_bound`'s
(Oler's bound, `robotarium_exp.packing`). Which robot takes which slot, and trading them on the way, is
`vtube_planning.onboard.parking`'s; whether the slots fit the testbed is `robotarium_exp.fit`'s verdict.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.packing import oler_bound
from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.geometry.tube import VirtualTube

FloatArray = NDArray[np.float64]

PARKING_SPACING_M = 0.3
"""Between parking lanes and rows: the safety filter keeps 0.2 m between control points, and a robot must pass
between parked ones (at 0.25 m, eight robots on the trapezoid deadlocked short of their slots)."""
PARKING_WALL_M = 0.2
"""Between a parking slot and the arena's edge: the barrier keeps control points 0.1 m (R / 2) from the edge, and
a robot turning into its slot needs another 0.1 m."""
PARKING_DEPTH_M = 1.0
"""The farthest parking row lies at most this far beyond the exit (less where the arena ends sooner)."""
PARKING_NEAREST_M = 0.08
"""The nearest parking row lies at least this far beyond the exit (a body, 0.055 m, with 2.5 cm to spare): a robot
parked behind the exit line stands on the tube's walls and in the way of the robots still passing (12 robots in a
0.6 m tube: 2130 robot-steps with a body on a wall)."""
PARKING_LANES_MAX = 6
"""At most this many parking lanes side by side (1.5 m across: the arena's 2 m less 0.2 m at each edge holds six;
with five, twelve robots on the straight sweep tubes had no room beyond the exit)."""


def parking(tube: VirtualTube, n_robots: int) -> FloatArray:
    """Slots (2, N) beyond the exit, filled farthest first: the most lanes (at most `PARKING_LANES_MAX`)
    whose slots all keep `PARKING_WALL_M` from the arena's edge with the nearest row at least
    `PARKING_NEAREST_M` beyond the exit, the farthest row at most `PARKING_DEPTH_M` beyond it or where
    the arena ends sooner. Lanes centred on the exit first; where none fit, lanes moved across (`_moved_across`:
    the curve's exit lies 0.3 m off the arena's middle, where four lanes fit centred and six moved to the middle);
    where no lanes do, staggered rows (`_staggered`); when no layout does, the centred lanes that come closest (the
    fit verdict then refuses them)."""
    end, tangent = tube.center_at(tube.length_m), tube.tangent(tube.length_m)
    lane_counts = range(min(n_robots, PARKING_LANES_MAX), 0, -1)
    layouts = []
    for lanes in lane_counts:
        rows_behind = PARKING_SPACING_M * ((n_robots - 1) // lanes)  # from the farthest row to the nearest
        lower, upper = _moves(slots_in_lanes(end, tangent, n_robots, lanes, 0.0), tangent)
        depth = min(PARKING_DEPTH_M, upper)  # the deepest the arena and the depth rule allow
        if depth < lower:  # none: the slots keep the edge only deeper than the rule allows, or nowhere
            depth = -math.inf
        if depth - rows_behind >= PARKING_NEAREST_M - 1e-9:
            return slots_in_lanes(end, tangent, n_robots, lanes, depth)
        layouts.append((depth - rows_behind, lanes))
    for lanes in lane_counts:
        moved = _moved_across(end, tangent, n_robots, lanes)
        if moved is not None:
            return moved
    staggered = _staggered(end, tangent, n_robots)
    if staggered is not None:
        return staggered
    nearest, lanes = max(layouts)
    depth = nearest + PARKING_SPACING_M * ((n_robots - 1) // lanes) if math.isfinite(nearest) else 0.0
    return slots_in_lanes(end, tangent, n_robots, lanes, depth)


PARKING_SCAN_M = 1e-3
"""The depths `_moved_across` tries, this far apart."""


def _moved_across(end: FloatArray, tangent: FloatArray, n_robots: int, lanes: int) -> FloatArray | None:
    """``lanes`` lanes moved across the exit (along its normal) at the deepest depth (to `PARKING_SCAN_M`) at which
    some move keeps the parking rules (`parking`), moved the least there; None where no move does."""
    normal = np.array([-tangent[1], tangent[0]])
    nearest = PARKING_SPACING_M * ((n_robots - 1) // lanes) + PARKING_NEAREST_M
    depths = np.arange(PARKING_DEPTH_M, nearest - 1e-9, -PARKING_SCAN_M)
    slots = slots_in_lanes(end, tangent, n_robots, lanes, depths[:, None, None])  # (depths, 2, N): every depth at once
    lower, upper = _moves_each(slots.min(axis=2).T, slots.max(axis=2).T, normal)
    found = np.flatnonzero(lower <= upper)
    if found.size == 0:
        return None
    k = int(found[0])  # the deepest
    move = min(max(0.0, float(lower[k])), float(upper[k]))
    return slots_in_lanes(end + move * normal, tangent, n_robots, lanes, float(depths[k]))


def parking_bound(tube: VirtualTube) -> int:
    """Oler's bound (`robotarium_exp.packing.oler_bound`) on how many slots `PARKING_SPACING_M` apart the room
    beyond ``tube``'s exit holds: from `PARKING_NEAREST_M` to `PARKING_DEPTH_M` beyond it, `PARKING_WALL_M` from
    the arena's edge (a convex region: the bound holds for every layout)."""
    end, tangent = tube.center_at(tube.length_m), tube.tangent(tube.length_m)
    return oler_bound(_room_beyond(end, tangent), PARKING_SPACING_M)


def _room_beyond(end: FloatArray, tangent: FloatArray) -> FloatArray:
    """Points (n, 2) whose convex hull is the room beyond the exit (`parking_bound`): the ends of its cross-sections
    every `PARKING_SCAN_M` in depth."""
    depths = np.arange(PARKING_NEAREST_M, PARKING_DEPTH_M + 1e-9, PARKING_SCAN_M)
    lower, upper = _cross_sections(end, tangent, depths)
    kept = lower <= upper
    centres = end[None, :] + depths[kept, None] * tangent[None, :]
    normal = np.array([-tangent[1], tangent[0]])
    ends: FloatArray = np.concatenate([centres + lower[kept, None] * normal, centres + upper[kept, None] * normal])
    return ends


def _cross_sections(end: FloatArray, tangent: FloatArray, depths: FloatArray) -> tuple[FloatArray, FloatArray]:
    """For each of ``depths`` beyond the exit, the moves along the exit's normal that keep a point there
    `PARKING_WALL_M` from the arena's edge, as lower and upper ends (lower > upper: none does)."""
    points = end[:, None] + depths[None, :] * tangent[:, None]
    return _moves_each(points, points, np.array([-tangent[1], tangent[0]]))


STAGGER_FAR_STEP_M = 0.01
"""The depths of the farthest staggered row `_staggered` tries, this far apart from the deepest down."""
STAGGER_FAR_SPAN_M = 0.3
"""How far below the deepest depth the farthest staggered row may stand (a room that narrows to a point, an exit
heading into a corner, holds a slot at its tip only in a sliver)."""


def _staggered(end: FloatArray, tangent: FloatArray, n_robots: int) -> FloatArray | None:
    """Slots (2, N) in the fewest rows that hold them, spread evenly from the farthest row's depth (the deepest a
    slot can have, at most `PARKING_DEPTH_M`; where no rows from there hold them, the deepest up to
    `STAGGER_FAR_SPAN_M` less that does) to `PARKING_NEAREST_M`, each row shifted half a pitch across from the
    next; rows nearer than the spacing get the wider pitch that keeps neighbours in the next row the spacing apart
    (rows two apart stand in the same lanes, so at least the spacing apart); every slot `PARKING_WALL_M` from the
    edge. The farthest rows are filled first, the nearest row's outermost slots (the exit's front stays free).
    None: no rows hold N."""
    room = _room_beyond(end, tangent)
    if room.shape[0] == 0:
        return None
    deepest, spacing = float(np.max((room - end) @ tangent)), PARKING_SPACING_M
    fars = deepest - np.arange(0.0, STAGGER_FAR_SPAN_M + 1e-9, STAGGER_FAR_STEP_M)
    for far in fars[fars > PARKING_NEAREST_M]:
        for rows in range(2, n_robots + 1):
            step = min(spacing, (far - PARKING_NEAREST_M) / (rows - 1))
            if rows > 2 and 2.0 * step < spacing:
                break  # more rows would stand nearer than half the spacing
            pitch = max(spacing, 2.0 * math.sqrt(max(spacing**2 - step**2, 0.0))) + 1e-9
            depths: FloatArray = far - step * np.arange(rows, dtype=float)
            found = _rows_across(end, tangent, depths, pitch, n_robots)
            if found is not None:
                return found
    return None


def _rows_across(
    end: FloatArray, tangent: FloatArray, depths: FloatArray, pitch: float, n_robots: int
) -> FloatArray | None:
    """`_staggered`'s slots for rows at ``depths`` (farthest first) with lanes ``pitch`` apart, odd rows shifted
    half a pitch: the shift of the lanes across (scanned every `PARKING_SCAN_M`) that holds the most slots, the
    one nearest the exit's axis among those; None when it holds fewer than N."""
    normal = np.array([-tangent[1], tangent[0]])
    lower, upper = _cross_sections(end, tangent, depths)
    lanes = np.arange(-math.ceil(4.0 / pitch), math.ceil(4.0 / pitch) + 1)  # the arena's diagonal is 3.8 m
    shifts = np.arange(0.0, pitch, PARKING_SCAN_M)
    halves = 0.5 * (np.arange(depths.size) % 2)
    across = shifts[:, None, None] + pitch * (lanes[None, None, :] + halves[None, :, None])  # (shifts, rows, lanes)
    inside = (across >= lower[None, :, None] - 1e-12) & (across <= upper[None, :, None] + 1e-12)
    count = inside.sum(axis=(1, 2))
    centre = np.abs(np.where(inside, across, 0.0).sum(axis=(1, 2)) / np.maximum(count, 1))
    best = int(np.lexsort((centre, -count))[0])  # the most slots, then the nearest the exit's axis
    if count[best] < n_robots:
        return None
    chosen: list[FloatArray] = []
    for depth, offsets, kept in zip(depths, across[best], inside[best]):
        row = offsets[kept]
        take = row[np.argsort(-np.abs(row), kind='stable')][: n_robots - len(chosen)]
        chosen += [end + depth * tangent + a * normal for a in np.sort(take)]
    slots: FloatArray = np.array(chosen).T
    return slots


def _moves(slots: FloatArray, direction: FloatArray) -> tuple[float, float]:
    """The moves of slots (2, N) along a unit ``direction`` that keep every one `PARKING_WALL_M` from the arena's
    edge, as an interval (lower > upper: none does)."""
    lower, upper = _moves_each(slots.min(axis=1, keepdims=True), slots.max(axis=1, keepdims=True), direction)
    return float(lower[0]), float(upper[0])


def _moves_each(lows: FloatArray, highs: FloatArray, direction: FloatArray) -> tuple[FloatArray, FloatArray]:
    """For each column k, the moves along a unit ``direction`` that keep the box from ``lows[:, k]`` to
    ``highs[:, k]`` (a point: the two alike) `PARKING_WALL_M` from the arena's edge, as lower and upper ends (lower >
    upper: none does)."""
    x0, x1, y0, y1 = ROBOTARIUM.arena_m
    w = PARKING_WALL_M
    lower, upper = np.full(lows.shape[1], -math.inf), np.full(lows.shape[1], math.inf)
    for axis, (low, high) in enumerate(((x0 + w, x1 - w), (y0 + w, y1 - w))):
        step = direction[axis]
        if abs(step) < 1e-12:
            outside = (lows[axis] < low) | (highs[axis] > high)
            lower, upper = np.where(outside, math.inf, lower), np.where(outside, -math.inf, upper)
            continue
        a, b = (low - lows[axis]) / step, (high - highs[axis]) / step  # the moves that bring the ends to the edges
        first, last = (a, b) if step > 0 else (b, a)  # not sorted: a set wider than the room has no move (first > last)
        lower, upper = np.maximum(lower, first), np.minimum(upper, last)
    return lower, upper


def slots_in_lanes(
    end: FloatArray, tangent: FloatArray, n_robots: int, lanes: int, depth_m: float | FloatArray
) -> FloatArray:
    """Slots (2, N) in ``lanes`` lanes and rows `PARKING_SPACING_M` apart, from ``depth_m`` beyond the exit
    backwards (depths shaped (D, 1, 1): every depth's slots at once, (D, 2, N))."""
    normal = np.array([-tangent[1], tangent[0]])
    depth, lane = np.divmod(np.arange(n_robots), lanes)
    along = depth_m - PARKING_SPACING_M * depth
    across = (lane - 0.5 * (lanes - 1)) * PARKING_SPACING_M
    slots: FloatArray = end[:, None] + along * tangent[:, None] + across * normal[:, None]
    return slots
