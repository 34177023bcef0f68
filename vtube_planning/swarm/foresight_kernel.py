"""The foresight's predictions, compiled (numba): every backup's flight over the horizon and what it comes closest to.

`vtube_planning.swarm.foresight` decides; this module flies its many predicted flights per period (robots x backups
x steps, each backup against every neighbour it checks), the part whose time grew with the swarm. Each prediction is
computed point by point with the same floating-point operations, in the same order, as the array code it replaced
(the tube's tables read through `vtube_planning.swarm.tube_tables`' compiled look-ups, a robot's response as
`vtube_planning.swarm.dynamics.respond` does), so a flight is the same to the last bit wherever numpy's own
functions are the C library's (``docs/theory.md`` §11, "Compiled"); ``tests/unit/vtube_planning/swarm/
test_foresight_kernel.py`` checks it against the array formulas. Only +, -, *, /, sqrt and the C library's cos, sin,
atan2, hypot are used (a complex exponential is a cos and a sin), none reordered or fused (numba's default: no
fast-math).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from vtube_planning.swarm.tube_tables import Grid, clearance_at, locate_point, maximum, minimum, table_row

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]


APART_SLACK_M = 1e-6
"""A neighbour is left out of a step's check when one coordinate of the separation stays beyond the distances that
count (2 r_s + margin, 2 r_p) by this much over the step (`_apart`): far beyond what rounding moves."""


@numba.njit(cache=True, inline='always')
def _apart(start: float, end: float, beyond: float) -> bool:
    """Whether a separation coordinate moving linearly from ``start`` to ``end`` stays at least ``beyond`` from 0."""
    return (start >= beyond and end >= beyond) or (start <= -beyond and end <= -beyond)


@numba.njit(cache=True)
def closest_squared(dx0: float, dy0: float, dx1: float, dy1: float) -> float:
    """The square of the closest two robots come over a step whose start and end separations are (dx0, dy0) and
    (dx1, dy1), both moving straight at constant speed over it: a crossing between two predicted points is not
    missed."""
    ex, ey = dx1 - dx0, dy1 - dy0
    t = -(dx0 * ex + dy0 * ey)
    squared = ex * ex + ey * ey
    t = minimum(maximum(t / maximum(squared, 1e-300), 0.0), 1.0)
    cx, cy = t * ex + dx0, t * ey + dy0
    return cx * cx + cy * cy


@numba.njit(cache=True)
def changing(
    speed: float, heading: float, new_speed: float, new_heading: float, step: float, a_v: float, a_n: float
) -> float:
    """How long, within ``step``, a robot's velocity changes from (``speed``, ``heading``) to the new one under
    (3), (4): its speed at a_v, its heading at a_n / new speed (`respond` turns by at most that, unwrapped)."""
    turning = abs(new_heading - heading) * new_speed / a_n
    return minimum(maximum(abs(new_speed - speed) / a_v, turning), step)


@numba.njit(cache=True)
def flights(
    robots: FloatArray,
    rows: IntArray,
    lane: FloatArray,
    speed_to: FloatArray,
    first: FloatArray,
    times: FloatArray,
    tables: Grid,
    limits: FloatArray,
) -> FloatArray:
    """(4, S, R, K): x, y, arc length and offset at the end of each of the S steps ``times`` of robots ``rows``
    (their x, y, speed, heading and arc length: the rows of ``robots``, (5, N)) flying backups (R, K): a ``lane`` and a
    speed ``speed_to``, the first step's target speed and heading given in ``first`` (2, R, K; NaN: the lane's).
    ``tables`` are the tube's (`TubeTables.compiled`); ``limits`` a_v, a_n, r_s, the lane's look-ahead time and the
    Newton steps that locate a point (`locate_point`). Over the first step, one period, a robot moves at its
    new velocity, as the simulator moves it; over a longer step its velocity changes linearly while (3), (4) let it
    (`changing`), then holds."""
    a_v, a_n, r_s, lookahead_s, locate_steps = limits[0], limits[1], limits[2], limits[3], int(limits[4])
    out = np.empty((4, times.size, lane.shape[0], lane.shape[1]))
    for r in numba.prange(lane.shape[0]):
        robot = rows[r]
        for k in range(lane.shape[1]):
            x, y, speed, heading = robots[0, robot], robots[1, robot], robots[2, robot], robots[3, robot]
            l_m = robots[4, robot]
            vx, vy = speed * math.cos(heading), speed * math.sin(heading)
            for index in range(times.size):
                step = times[index]
                if index == 0 and math.isfinite(first[1, r, k]):
                    target_speed, target = first[0, r, k], first[1, r, k]
                else:
                    target_speed = speed_to[r, k]
                    ahead = l_m + maximum(1.0, speed * lookahead_s)  # `TubeTables.lane_heading`
                    centre_x, centre_y = table_row(ahead, 0, tables), table_row(ahead, 1, tables)
                    angle, half_width = table_row(ahead, 2, tables), table_row(ahead, 4, tables)
                    lateral = lane[r, k] * maximum(half_width - r_s, 0.0)
                    goal_x = centre_x - lateral * math.sin(angle)
                    goal_y = centre_y + lateral * math.cos(angle)
                    target = math.atan2(goal_y - y, goal_x - x)
                # the response of `vtube_planning.swarm.dynamics.respond`
                new_speed = speed + minimum(maximum(target_speed - speed, -a_v * step), a_v * step)
                turned = np.exp(1j * (target - heading))
                turn = math.atan2(turned.imag, turned.real)
                max_turn = a_n * step / maximum(new_speed, 1e-12)
                new_heading = heading + minimum(maximum(turn, -max_turn), max_turn)
                ux, uy = new_speed * math.cos(new_heading), new_speed * math.sin(new_heading)
                if index == 0:
                    dx, dy = step * ux, step * uy
                else:
                    within = changing(speed, heading, new_speed, new_heading, step, a_v, a_n)
                    dx, dy = step * ux - 0.5 * within * (ux - vx), step * uy - 0.5 * within * (uy - vy)
                speed, heading, vx, vy = new_speed, new_heading, ux, uy
                x, y = x + dx, y + dy
                l_m, offset = locate_point(x, y, l_m + math.hypot(dx, dy), locate_steps, tables)
                out[0, index, r, k], out[1, index, r, k], out[2, index, r, k], out[3, index, r, k] = x, y, l_m, offset
    return out


@numba.njit(cache=True)
def foresee(
    flown: FloatArray,
    others: FloatArray,
    robots: FloatArray,
    rows: IntArray,
    near: IntArray,
    seen: IntArray,
    times: FloatArray,
    tables: Grid,
    bounds: FloatArray,
) -> FloatArray:
    """(3, R, K) for robots ``rows`` flying ``flown`` (`flights`, (4, S, R, K)) among neighbours ``near`` (R, M)
    flying ``others`` (2, S, N, C), each neighbour seen in its flight ``seen`` (R, M): the time of the first step
    closer than r_s + margin to a wall or 2 r_s + margin to a neighbour (inf: none), the time of the first contact
    (a centre outside the tube, or bodies closer than 2 r_p), and how far short they fall over the horizon, the
    integral over time of (r_s + margin - clearance)+ and (2 r_s + margin - the nearest neighbour's distance)+
    (m s). ``robots`` holds their positions (rows 0, 1), ``tables`` as in `flights`, ``bounds`` r_s, r_p, the
    margin and the tube's length (`clearance_at`). Two robots are checked at the closest they come between two
    predicted points (`closest_squared`); a robot is not its own neighbour; no wall is measured outside
    0 <= l <= L. Only a nearest distance below 2 r_s + margin or 2 r_p counts: a neighbour whose separation stays
    beyond both along one axis over a step (`_apart`) is not computed there, and the results are those of
    computing it."""
    r_s, r_p, margin_m, length_m = bounds[0], bounds[1], bounds[2], bounds[3]
    wall_short, body_short, touching = r_s + margin_m, 2.0 * r_s + margin_m, 2.0 * r_p
    apart = max(body_short, touching) + APART_SLACK_M
    count, width = near.shape[1], flown.shape[3]
    out = np.empty((3, rows.size, width))
    for r in numba.prange(rows.size):
        robot = rows[r]
        dx0, dy0 = np.empty(count), np.empty(count)
        for k in range(width):
            for m in range(count):
                dx0[m] = robots[0, robot] - robots[0, near[r, m]]
                dy0[m] = robots[1, robot] - robots[1, near[r, m]]
            first, contact, shortfall, elapsed = math.inf, math.inf, 0.0, 0.0
            for index in range(times.size):
                step = times[index]
                elapsed += step
                x, y, l_m = flown[0, index, r, k], flown[1, index, r, k], flown[2, index, r, k]
                clearance = clearance_at(l_m, flown[3, index, r, k], length_m, tables)
                least = math.inf
                for m in range(count):
                    other = near[r, m]
                    dx1 = x - others[0, index, other, seen[r, m]]
                    dy1 = y - others[1, index, other, seen[r, m]]
                    if other != robot and not (_apart(dx0[m], dx1, apart) or _apart(dy0[m], dy1, apart)):
                        least = minimum(least, closest_squared(dx0[m], dy0[m], dx1, dy1))
                    dx0[m], dy0[m] = dx1, dy1
                nearest = math.sqrt(least)
                short = maximum(wall_short - clearance, 0.0) + maximum(body_short - nearest, 0.0)
                shortfall = shortfall + step * short
                if short > 0.0 and first == math.inf:
                    first = elapsed
                if (clearance < 0.0 or nearest < touching) and contact == math.inf:
                    contact = elapsed
            out[0, r, k], out[1, r, k], out[2, r, k] = first, contact, shortfall
    return out


parallel_flights = numba.njit(parallel=True)(flights.py_func)
"""`flights` on all cores (numba's threads, one robot's backups each): the same bits, for large swarms
(`vtube_planning.swarm.foresight.ALL_CORES_FROM`); compiled on first use (not cached: a cache of the same
function's serial build would be read back for it)."""
parallel_foresee = numba.njit(parallel=True)(foresee.py_func)
"""`foresee` on all cores, as `parallel_flights`."""
