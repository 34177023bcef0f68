"""The compiled predictions against the array formulas they compute (an independent re-computation with numpy: the
tables through `TubeTables.at`, the response through `respond`): the same to the last bit where numpy's cos, sin
and atan2 are the C library's, as its hypot is (on a machine whose numpy uses its own SIMD versions, within 1e-9)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.swarm.dynamics import respond
from vtube_planning.swarm.foresight_kernel import APART_SLACK_M, flights, foresee
from vtube_planning.swarm.tube_tables import TubeTables, table_row

BENT = VirtualTube(
    ArcPath((ArcPiece(4.0), ArcPiece(9.0, radius_m=6.0), ArcPiece(3.0), ArcPiece(7.0, radius_m=5.0, left=False))),
    WidthProfile(2.5, (WidthPart('constant', 8.0), WidthPart('linear', 6.0, 1.2), WidthPart('constant', 9.0))),
)
TIMES = np.concatenate([[0.02], np.full(7, 2.98 / 7)])
R_S, R_P, LOOKAHEAD_S, LOCATE = 0.4, 0.2, 1.0, 2


def _libm_like() -> bool:
    """Whether numpy's cos, sin and atan2 give the C library's bits (Python's math module calls it; its hypot is
    its own): then the kernel's must be equal."""
    x = np.random.default_rng(0).normal(0.0, 5.0, (2, 4000))
    same = all(a == math.cos(v) for a, v in zip(np.cos(x[0]), x[0]))
    same &= all(a == math.sin(v) for a, v in zip(np.sin(x[0]), x[0]))
    return same and all(a == math.atan2(v, u) for a, v, u in zip(np.arctan2(x[0], x[1]), x[0], x[1]))


def _same(kernel: np.ndarray, reference: np.ndarray) -> None:
    if EXACT:
        np.testing.assert_array_equal(kernel, reference)
    else:
        np.testing.assert_allclose(kernel, reference, rtol=1e-9, atol=1e-9)


EXACT = _libm_like()


def _reference_locate(tables: TubeTables, x, y, l_m, steps):
    for _ in range(steps):
        centre_x, centre_y, angle, curvature = tables.at(l_m, slice(0, 4))
        dx, dy = x - centre_x, y - centre_y
        cos, sin = np.cos(angle), np.sin(angle)
        offset = dy * cos - dx * sin
        l_m = l_m + (dx * cos + dy * sin) / np.maximum(1.0 - curvature * offset, 0.1)
    return l_m, offset


def _reference_flights(tables: TubeTables, robots, rows, lane, speed_to, first, a_v, a_n):
    shape = lane.shape
    x, y, speed, heading, l_m = (np.broadcast_to(row[rows, None], shape) for row in robots)
    vx, vy = speed * np.cos(heading), speed * np.sin(heading)
    out = []
    for index, step in enumerate(TIMES):
        ahead = l_m + np.maximum(1.0, speed * LOOKAHEAD_S)
        centre_x, centre_y, angle, _, half_width = tables.at(ahead, slice(0, 5))
        lateral = lane * np.maximum(half_width - R_S, 0.0)
        target = np.arctan2(centre_y + lateral * np.cos(angle) - y, centre_x - lateral * np.sin(angle) - x)
        target_speed = speed_to
        if index == 0:
            given = np.isfinite(first[1])
            target, target_speed = np.where(given, first[1], target), np.where(given, first[0], speed_to)
        new_speed, new_heading = respond(speed, heading, target_speed, target, a_v, a_n, step)
        ux, uy = new_speed * np.cos(new_heading), new_speed * np.sin(new_heading)
        if index == 0:
            dx, dy = step * ux, step * uy
        else:
            turning = np.abs(new_heading - heading) * new_speed / a_n
            within = np.minimum(np.maximum(np.abs(new_speed - speed) / a_v, turning), step)
            dx, dy = step * ux - 0.5 * within * (ux - vx), step * uy - 0.5 * within * (uy - vy)
        speed, heading, vx, vy, x, y = new_speed, new_heading, ux, uy, x + dx, y + dy
        l_m, offset = _reference_locate(tables, x, y, l_m + np.hypot(dx, dy), LOCATE)
        out.append((x, y, l_m, offset))
    return np.array(out).transpose(1, 0, 2, 3)


def _reference_foresee(tables: TubeTables, flown, others, robots, rows, near, seen, margin, length_m=BENT.length_m):
    itself = np.where(near == rows[:, None], np.inf, 0.0)[:, None, :]
    dx0 = (robots[0, rows, None] - robots[0, near])[:, None, :]
    dy0 = (robots[1, rows, None] - robots[1, near])[:, None, :]
    first = np.full(flown.shape[2:], np.inf)
    contact, shortfall, elapsed = first.copy(), np.zeros(first.shape), 0.0
    for index, step in enumerate(TIMES):
        elapsed += step
        x, y, l_m, offset = flown[:, index]
        inside = (l_m >= 0.0) & (l_m <= length_m)
        clearance = np.where(inside, tables.at(l_m, slice(4, 5))[0] - np.abs(offset), np.inf)
        dx1 = x[:, :, None] - others[0, index][near, seen][:, None, :]
        dy1 = y[:, :, None] - others[1, index][near, seen][:, None, :]
        ex, ey = dx1 - dx0, dy1 - dy0
        t = np.clip(-(dx0 * ex + dy0 * ey) / np.maximum(ex * ex + ey * ey, 1e-300), 0.0, 1.0)
        nearest = np.sqrt(((t * ex + dx0) ** 2 + (t * ey + dy0) ** 2 + itself).min(axis=2))
        dx0, dy0 = dx1, dy1
        short = np.maximum(R_S + margin - clearance, 0.0) + np.maximum(2.0 * R_S + margin - nearest, 0.0)
        shortfall += step * short
        first[(short > 0.0) & np.isinf(first)] = elapsed
        contact[((clearance < 0.0) | (nearest < 2.0 * R_P)) & np.isinf(contact)] = elapsed
    return np.array([first, contact, shortfall])


def _swarm(rng: np.random.Generator, n: int) -> tuple[TubeTables, np.ndarray]:
    tables = TubeTables.of(BENT, 20.0, window_m=2.0)
    l_m = rng.uniform(-1.0, BENT.length_m, n)
    offset = rng.uniform(-2.0, 2.0, n)
    x, y, angle = (tables.at(l_m, slice(k, k + 1))[0] for k in (0, 1, 2))
    positions = np.vstack([x - offset * np.sin(angle), y + offset * np.cos(angle)])
    heading = angle + rng.normal(0.0, 0.4, n)
    return tables, np.vstack([positions, rng.uniform(2.0, 5.0, n), heading, l_m])


@pytest.mark.parametrize('limited', [True, False])
def test_the_compiled_flights_are_the_array_formulas(limited: bool) -> None:
    rng = np.random.default_rng(11)
    tables, robots = _swarm(rng, 30)
    rows = rng.choice(30, 12, replace=False)
    lane, speed_to = rng.uniform(-1.0, 1.0, (12, 7)), rng.uniform(2.0, 5.0, (12, 7))
    given = rng.random((12, 7)) < 0.5  # half the backups with the first period's target given
    first = np.stack([rng.uniform(2.0, 5.0, (12, 7)), np.where(given, rng.normal(0.0, 1.0, (12, 7)), np.nan)])
    a_v, a_n = (1.0, 1.0) if limited else (math.inf, math.inf)
    limits = np.array([a_v, a_n, R_S, LOOKAHEAD_S, LOCATE])
    flown = flights(robots, rows, lane, speed_to, first, TIMES, tables.compiled, limits)
    _same(flown, _reference_flights(tables, robots, rows, lane, speed_to, first, a_v, a_n))
    assert np.isfinite(flown).all()


def test_the_compiled_check_is_the_array_formulas() -> None:
    rng = np.random.default_rng(12)
    tables, robots = _swarm(rng, 25)
    rows = np.arange(25)
    lane, speed_to = rng.uniform(-1.0, 1.0, (25, 3)), rng.uniform(2.0, 5.0, (25, 3))
    flown = flights(
        robots,
        rows,
        lane,
        speed_to,
        np.full((2, 25, 3), np.nan),
        TIMES,
        tables.compiled,
        np.array([1.0, 1.0, R_S, LOOKAHEAD_S, LOCATE]),
    )
    others = np.ascontiguousarray(flown[:2, :, :, :2])
    near = np.array([rng.choice(25, 6, replace=False) for _ in range(25)])
    near[:, 0] = rows  # each robot among its own neighbours: never its own nearest
    seen = rng.integers(0, 2, near.shape)
    for margin in (0.0, 0.1):
        found = foresee(
            flown, others, robots, rows, near, seen, TIMES, tables.compiled, np.array([R_S, R_P, margin, BENT.length_m])
        )
        reference = _reference_foresee(tables, flown, others, robots, rows, near, seen, margin)
        _same(found, reference)
    assert np.isfinite(found[0]).any() and np.isinf(found[0]).any()  # both safe and unsafe flights in the sample
    assert (found[2] > 0.0).any()


def test_a_table_look_up_is_the_array_interpolation() -> None:
    tables = TubeTables.of(BENT, 3.0, window_m=1.0)
    l_m = np.random.default_rng(13).uniform(-6.0, BENT.length_m + 6.0, 300)  # beyond both ends too
    for row in range(5):
        looked_up = np.array([table_row(value, row, tables.compiled) for value in l_m])
        np.testing.assert_array_equal(looked_up, tables.at(l_m, slice(row, row + 1))[0])  # + - * only: exact


def test_neighbours_left_out_at_the_threshold_change_nothing() -> None:
    # pairs of robots in a wide straight tube (no wall near) flying side by side along x, their separation along x
    # within micrometres of 2 r_s + margin (+ the slack) at the start and at every predicted point: the check leaves
    # out those beyond the slack and computes the others; the results must be the array formula's, which computes
    # them all, and some robots fall micrometres short (the threshold straddled)
    wide = VirtualTube(ArcPath((ArcPiece(80.0),)), WidthProfile(20.0, (WidthPart('constant', 80.0),)))
    tables = TubeTables.of(wide, 20.0)
    rng = np.random.default_rng(14)
    threshold = 2.0 * R_S + 0.1 + APART_SLACK_M
    pairs = 20
    x = np.concatenate([np.linspace(5.0, 60.0, pairs), np.zeros(pairs)])
    gap = threshold + rng.choice([-2e-6, -1e-6, 0.0, 1e-6, 2e-6], pairs)  # the second of a pair behind the first
    x[pairs:] = x[:pairs] - gap
    y = np.concatenate([np.linspace(-8.0, 8.0, pairs)] * 2)
    robots = np.vstack([x, y, np.full(2 * pairs, 3.0), np.zeros(2 * pairs), x])
    rows = np.arange(2 * pairs)
    flown = flights(
        robots,
        rows,
        np.zeros((2 * pairs, 1)),
        np.full((2 * pairs, 1), 3.0),
        np.full((2, 2 * pairs, 1), np.nan),
        TIMES,
        tables.compiled,
        np.array([1.0, 1.0, R_S, LOOKAHEAD_S, LOCATE]),
    )
    partner = np.concatenate([rows[pairs:], rows[:pairs]])
    near = np.column_stack([rows, partner])  # itself, then its partner
    others = np.ascontiguousarray(np.repeat(flown[:2], 2, axis=3))
    for r, other in zip(rows, partner):  # its partner seen (view 1) exactly the gap away along x at every point
        others[0, :, other, 1] = flown[0, :, r, 0] + (gap[r - pairs] if r >= pairs else -gap[r])
        others[1, :, other, 1] = flown[1, :, r, 0]
    seen = np.column_stack([np.zeros(2 * pairs, dtype=np.intp), np.ones(2 * pairs, dtype=np.intp)])
    bounds = np.array([R_S, R_P, 0.1, wide.length_m])
    found = foresee(flown, others, robots, rows, near, seen, TIMES, tables.compiled, bounds)
    _same(found, _reference_foresee(tables, flown, others, robots, rows, near, seen, 0.1, wide.length_m))
    short = found[2, :, 0]
    assert (short == 0.0).any() and ((short > 0.0) & (short < 1e-4)).any()  # both sides of the threshold
