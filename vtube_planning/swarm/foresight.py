"""Foresight: the safety layer of a speed- and acceleration-limited swarm (``docs/theory.md`` §11).

A robot of the paper's model (1)-(4) cannot stop (v >= v_min) and changes its velocity slowly (a_v, a_n), so the
law's command (s1), which assumes a velocity that changes at once, can be a command the robot cannot fly in time:
flown under (3), (4) every mode collided and left the tube. The foresight keeps the law where the law is safe and
overrides it where it is not, the way a safety filter with a backup does. A *backup* is a lane and a speed: fly at
speed s along the tube at the lateral offset eta (lambda(l) - r_s), eta in [-1, 1], which narrows and bends with the
tube. Every period, for every robot:

1. the law's command is safe if, after one period of following it, the robot can keep its lane (its present eta)
   at the law's speed for the horizon T without coming closer than r_s to a wall or 2 r_s to a neighbour, with
   `LAW_MARGIN_M` to spare; the walls are the narrowest half-width over the `merge_window` ahead;
2. the neighbours fly the backups they announced the period before (each robot announces its lane and speed);
3. a safe law's command stands; otherwise the robot flies the safe backup whose first command is closest to the
   law's, or, when none is safe, the one whose first contact comes latest (then its first shortfall, then how far
   short it falls), keeping the backup it announced over a barely better one (`KEEP_M_S`, `KEEP_MPS`), and keeps
   flying backups for `HOLD_S` before the law again; two robots are checked at the closest they come between two
   predicted points, not only at the points; the robots choose twice (`PASSES`), the second time each against
   the choices just made by the robots ahead of it, so that two robots side by side do not both turn into one gap;
4. the robot is commanded its velocity after one period of following the target: a command inside (2)-(4) from
   its present velocity.

Every prediction follows the robot's response under (3), (4) (`vtube_planning.swarm.dynamics.respond`, the
simulator's own physics). Predicted points are located on the tube through its tables
(`vtube_planning.swarm.tube_tables`), by Newton steps from the arc length the path predicts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.params import ControlParams, SwarmParams
from vtube_planning.swarm.dynamics import respond
from vtube_planning.swarm.tube_tables import TubeTables

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]
Flight = tuple[FloatArray, ...]
"""One step of predicted flights: x, y, arc length l and offset y_tube, each (R, K)."""

LANES = np.array([-1.0, -0.5, 0.0, 0.5, 1.0])
"""The backups' lanes eta (besides the robot's present one), each at every speed of `SPEED_FRACTIONS`."""
SPEED_FRACTIONS = np.array([0.0, 0.5, 1.0])
"""The backups' speeds, as fractions of the way from v_min to v_max."""
PASSES = 2
"""How many times the risky robots choose in a period; from the second on, each sees the choices just made by the
risky robots ahead of it (larger arc length) instead of their announcements of the period before."""
LANE_LOOKAHEAD_S = 1.0
"""A backup steers for its lane at the point this many seconds of flight ahead (at least 1 m)."""
PREDICTION_LOCATE_STEPS = 2
"""Newton steps locating a predicted point, from the arc length flown (at most 2.2 m a step, off by the bend's
share of it: a few decimetres, then millimetres after one step, far less after two)."""
SUB_STEPS = 7
"""The horizon after the first period is predicted in this many equal steps."""
LAW_MARGIN_M = 0.1
"""The law's command stands only with this much room to spare beyond r_s and 2 r_s: the backups take over before
the safe distances are reached, not at them."""
HOLD_S = 1.0
"""A robot whose law's command was unsafe flies backups for this long before the law again: two robots that each
make the other's law unsafe would otherwise take turns, one period the law, the next a backup, and fly neither."""
KEEP_M_S = 0.1
"""A robot whose announced backup falls short keeps it unless another falls short by this much less (m s) or later:
two backups equally short would otherwise take turns, and neither be flown."""
KEEP_MPS = 0.5
"""A robot whose announced backup is safe keeps it unless another safe one's first command is this much closer to
the law's (m/s): the nearest to the law changes with the speed, and two backups taken in turn are neither flown."""
ALL_PAIRS_UP_TO = 64
"""Swarms of up to this many robots check every neighbour; larger ones the nearest `NEIGHBOURS`."""
NEIGHBOURS = 20
"""How many nearest neighbours a robot of a larger swarm checks: with 10, three of five planned runs of 80 robots
in scene C collided (a robot closing in from beyond the ten nearest of a dense crowd is not seen); with 20 those
three did not (``docs/theory.md`` §11, "Which neighbours")."""


def default_horizon(swarm: SwarmParams) -> float:
    """The foresight's horizon T when none is given: (v_max - v_min) / a_v, the time the largest speed change
    takes, and at least 1 s (s)."""
    return max(1.0, (swarm.v_max_mps - swarm.v_min_mps) / swarm.a_v_mps2)


def with_foresight(control: ControlParams, swarm: SwarmParams) -> ControlParams:
    """``control`` flown under the foresight: its own horizon ``foresight_s``, else `default_horizon`."""
    return replace(control, foresight_s=control.foresight_s or default_horizon(swarm))


def foresight_for(
    tube: VirtualTube, swarm: SwarmParams, control: ControlParams, acceleration_limits: bool
) -> Foresight | None:
    """The foresight ``control`` asks for (None when its horizon is 0: the law alone)."""
    if control.foresight_s <= 0:
        return None
    return Foresight(tube, swarm, horizon_s=control.foresight_s, acceleration_limits=acceleration_limits)


def merge_window(swarm: SwarmParams) -> float:
    """How far ahead the foresight sees a narrowing: sqrt(3) v_min^2 / a_n, the distance an S-turn at v_min flies
    to move a robot sideways by one turning radius v_min^2 / a_n (m)."""
    return math.sqrt(3.0) * swarm.v_min_mps**2 / swarm.a_n_mps2


@dataclass(frozen=True)
class _Robots:
    """The robots now: positions (2, N), speeds, headings, arc lengths, offsets and lanes (N,)."""

    positions: FloatArray
    speed: FloatArray
    heading: FloatArray
    l_m: FloatArray
    offset_m: FloatArray
    lane: FloatArray


@dataclass(frozen=True)
class _Backups:
    """(R, K) backups of robots ``rows``: lanes and speeds, and the target of their first period (NaN: the lane's)."""

    rows: IntArray
    lane: FloatArray
    speed: FloatArray
    first_speed: FloatArray
    first_heading: FloatArray


class Foresight:
    """The foresight of a swarm, with its state (every robot's announced backup).

    ``horizon_s`` is T (`default_horizon` is the usual choice). With ``acceleration_limits`` the robots
    obey (3), (4); without, a velocity changes at once (the paper's model) and the foresight predicts that.
    """

    def __init__(self, tube: VirtualTube, swarm: SwarmParams, *, horizon_s: float, acceleration_limits: bool) -> None:
        self.swarm = swarm
        self.horizon_s = float(horizon_s)
        self.a_v = swarm.a_v_mps2 if acceleration_limits else math.inf
        self.a_n = swarm.a_n_mps2 if acceleration_limits else math.inf
        window = merge_window(swarm) if acceleration_limits else 0.0
        self.tables = TubeTables.of(tube, swarm.v_max_mps * self.horizon_s + 2.0 * swarm.r_a_m, window)
        self._tree = cKDTree(self.tables.stacked[:2].T)
        self.announced: tuple[FloatArray, FloatArray] | None = None  # every robot's lane and speed
        self.overridden = 0  # robot-periods where the law's command was replaced
        self._held: FloatArray | float = 0.0  # per robot, how much longer it flies a backup before the law again

    def __call__(self, positions: FloatArray, velocity: FloatArray, command: FloatArray, dt_s: float) -> FloatArray:
        """The commands (2, N) for robots at ``positions`` flying ``velocity`` whose law commands ``command``."""
        speed, heading = np.hypot(velocity[0], velocity[1]), np.arctan2(velocity[1], velocity[0])
        law_speed = np.clip(np.hypot(command[0], command[1]), self.swarm.v_min_mps, self.swarm.v_max_mps)
        law_heading = np.arctan2(command[1], command[0])
        target_speed, target_heading = self._decide(positions, speed, heading, law_speed, law_heading, dt_s)
        new_speed, new_heading = respond(speed, heading, target_speed, target_heading, self.a_v, self.a_n, dt_s)
        commanded: FloatArray = new_speed * np.vstack([np.cos(new_heading), np.sin(new_heading)])
        return commanded

    def _decide(
        self,
        positions: FloatArray,
        speed: FloatArray,
        heading: FloatArray,
        law_speed: FloatArray,
        law_heading: FloatArray,
        dt_s: float,
    ) -> tuple[FloatArray, FloatArray]:
        """Each robot's law checked as one period of its command then its lane, the backups of the robots whose law
        is unsafe (or held) chosen and announced; the targets (speeds, headings)."""
        l_guess = self.tables.l_m[self._tree.query(positions.T)[1]]
        l_m, offset = self.tables.locate(positions[0], positions[1], l_guess)
        lane = self.tables.lane_of(l_m, offset, self.swarm.r_s_m)
        robots = _Robots(positions, speed, heading, l_m, offset, lane)
        announced = self.announced if self.announced is not None else (lane, speed)
        rows, free = np.arange(speed.size), np.full(speed.size, np.nan)
        both = _Backups(  # column 0: the backup each announced (its neighbours' view), 1: its law's command
            rows,
            np.column_stack([announced[0], lane]),
            np.column_stack([announced[1], law_speed]),
            np.column_stack([free, law_speed]),
            np.column_stack([free, law_heading]),
        )
        flights = self._flights(robots, both, dt_s)
        others = [(x[:, :1], y[:, :1]) for x, y, _, _ in flights]
        neighbours = self._neighbours(positions)
        law = [tuple(a[:, 1:] for a in flight) for flight in flights]
        first = self._foresee(robots, rows, law, others, neighbours, dt_s, LAW_MARGIN_M)[0][:, 0]
        target_speed, target_heading = law_speed.copy(), law_heading.copy()
        announced_lane, announced_speed = lane.copy(), law_speed.copy()
        unsafe = np.isfinite(first)
        self._held = np.where(unsafe, HOLD_S, np.maximum(self._held - dt_s, 0.0))
        risky = np.flatnonzero(unsafe | (self._held > 0.0))
        if risky.size:
            chosen_lane, chosen_speed = self._choose(
                robots, risky, law_speed, law_heading, announced, others, neighbours, dt_s
            )
            announced_lane[risky], announced_speed[risky] = chosen_lane, chosen_speed
            target_speed[risky] = chosen_speed
            target_heading[risky] = self._steer(
                positions[0, risky], positions[1, risky], l_m[risky], chosen_lane, speed[risky]
            )
            self.overridden += risky.size
        self.announced = (announced_lane, announced_speed)
        return target_speed, target_heading

    def _steer(self, x: FloatArray, y: FloatArray, l_m: FloatArray, lane: FloatArray, speed: FloatArray) -> FloatArray:
        """The heading that steers for ``lane`` from (x, y) at arc length l and ``speed``."""
        ahead = np.maximum(1.0, speed * LANE_LOOKAHEAD_S)
        return self.tables.lane_heading(x, y, l_m, lane, self.swarm.r_s_m, ahead)

    def _times(self, dt_s: float) -> FloatArray:
        """The step lengths of a prediction: one period, then `SUB_STEPS` equal steps to the horizon."""
        rest = max(self.horizon_s - dt_s, dt_s)
        return np.concatenate([[dt_s], np.full(SUB_STEPS, rest / SUB_STEPS)])

    def _flights(self, robots: _Robots, backups: _Backups, dt_s: float) -> list[Flight]:
        """Each step's (x, y, l, y_tube) of robots ``backups.rows`` flying their backups (R, K). Over the first step,
        one period, a robot moves at its new velocity, as the simulator moves it; over a longer step its velocity
        changes linearly while (3), (4) let it (`_changing`), then holds (moved at the new velocity over a long step
        instead, a robot braking at a_v would fall short by a_v step^2 / 2: 9 cm in 0.43 s at 1 m/s^2)."""
        rows, shape = backups.rows, backups.lane.shape
        speed = np.broadcast_to(robots.speed[rows, None], shape)
        heading = np.broadcast_to(robots.heading[rows, None], shape)
        vx, vy = speed * np.cos(heading), speed * np.sin(heading)
        x, y = robots.positions[0, rows, None], robots.positions[1, rows, None]
        l_m = np.broadcast_to(robots.l_m[rows, None], shape)
        offset = np.broadcast_to(robots.offset_m[rows, None], shape)
        out: list[Flight] = []
        for index, step in enumerate(self._times(dt_s)):
            target = self._steer(x, y, l_m, backups.lane, speed)
            target_speed = backups.speed
            if index == 0:
                given = np.isfinite(backups.first_heading)
                target = np.where(given, backups.first_heading, target)
                target_speed = np.where(given, backups.first_speed, target_speed)
            new_speed, new_heading = respond(speed, heading, target_speed, target, self.a_v, self.a_n, step)
            ux, uy = new_speed * np.cos(new_heading), new_speed * np.sin(new_heading)
            if index == 0:
                dx, dy = step * ux, step * uy
            else:
                changing = self._changing(speed, heading, new_speed, new_heading, step)
                dx, dy = step * ux - 0.5 * changing * (ux - vx), step * uy - 0.5 * changing * (uy - vy)
            speed, heading, vx, vy = new_speed, new_heading, ux, uy
            x, y = x + dx, y + dy
            l_m, offset = self.tables.locate(x, y, l_m + np.hypot(dx, dy), PREDICTION_LOCATE_STEPS)
            out.append((x, y, l_m, offset))
        return out

    def _changing(
        self, speed: FloatArray, heading: FloatArray, new_speed: FloatArray, new_heading: FloatArray, step: float
    ) -> FloatArray:
        """How long, within ``step``, a robot's velocity changes from (``speed``, ``heading``) to the new one under
        (3), (4): its speed at a_v, its heading at a_n / new speed (`respond` turns by at most that, unwrapped)."""
        turning = np.abs(new_heading - heading) * new_speed / self.a_n
        changing: FloatArray = np.minimum(np.maximum(np.abs(new_speed - speed) / self.a_v, turning), step)
        return changing

    def _neighbours(self, positions: FloatArray) -> IntArray:
        """(N, M) indices of the robots each robot checks (itself as padding where it has fewer)."""
        n = positions.shape[1]
        if n <= ALL_PAIRS_UP_TO:
            return np.tile(np.arange(n), (n, 1))
        tree = cKDTree(positions.T, balanced_tree=False, compact_nodes=False)  # built every period: built fast
        return np.asarray(tree.query(positions.T, k=min(n, NEIGHBOURS + 1))[1], dtype=np.intp)

    def _foresee(
        self,
        robots: _Robots,
        rows: IntArray,
        flights: list[Flight],
        others: list[tuple[FloatArray, FloatArray]],
        neighbours: IntArray,
        dt_s: float,
        margin_m: float = 0.0,
        seen: IntArray | None = None,
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(R, K) for robots ``rows`` flying ``flights`` (`_flights`): the time of the first step closer than r_s to a
        wall or 2 r_s to a neighbour (inf: none), the time of the first contact (a centre outside the tube, or
        bodies closer than 2 r_p), and how far short they fall over the horizon, the integral over time of
        (r_s - clearance)+ and (2 r_s - the nearest neighbour's distance)+ (m s)."""
        shape, r_s = flights[0][0].shape, self.swarm.r_s_m
        near = neighbours[rows]  # (R, M)
        view = np.zeros_like(near) if seen is None else seen  # which flight of ``others`` each neighbour is seen in
        seen_at = near * others[0][0].shape[1] + view  # the flat index of that flight's point
        itself = np.where(near == rows[:, None], np.inf, 0.0)[:, None, :]  # a robot is not its own neighbour
        shortfall, first, contact = np.zeros(shape), np.full(shape, np.inf), np.full(shape, np.inf)
        elapsed = 0.0
        dx0 = robots.positions[0, rows, None, None] - robots.positions[0, near][:, None, :]
        dy0 = robots.positions[1, rows, None, None] - robots.positions[1, near][:, None, :]
        for step, (x, y, l_m, offset), (ox, oy) in zip(self._times(dt_s), flights, others):
            elapsed += step
            clearance = self.tables.clearance(l_m, offset)
            ox, oy = np.take(ox, seen_at), np.take(oy, seen_at)
            dx1, dy1 = x[:, :, None] - ox[:, None, :], y[:, :, None] - oy[:, None, :]
            squared = _closest_squared(dx0, dy0, dx1, dy1)
            nearest = np.sqrt(np.add(squared, itself, out=squared).min(axis=2))
            dx0, dy0 = dx1, dy1
            short = np.maximum(r_s + margin_m - clearance, 0.0) + np.maximum(2.0 * r_s + margin_m - nearest, 0.0)
            shortfall += step * short
            first[(short > 0.0) & np.isinf(first)] = elapsed
            contact[((clearance < 0.0) | (nearest < 2.0 * self.swarm.r_p_m)) & np.isinf(contact)] = elapsed
        return first, contact, shortfall

    def _choose(
        self,
        robots: _Robots,
        risky: IntArray,
        law_speed: FloatArray,
        law_heading: FloatArray,
        announced: tuple[FloatArray, FloatArray],
        others: list[tuple[FloatArray, FloatArray]],
        neighbours: IntArray,
        dt_s: float,
    ) -> tuple[FloatArray, FloatArray]:
        """The backups (lanes, speeds) of the ``risky`` robots (`_best`), chosen `PASSES` times: first each against
        its neighbours' announcements, then each again against the choices just made by the risky robots ahead of
        it. Two robots side by side that choose at once from each other's old announcements can both turn into the
        gap between them; in order, the one behind sees what the one ahead just chose."""
        swarm = self.swarm
        band = swarm.v_min_mps + SPEED_FRACTIONS * (swarm.v_max_mps - swarm.v_min_mps)
        lanes = np.concatenate([np.tile(LANES, (risky.size, 1)), robots.lane[risky, None]], axis=1)
        kept_lane, kept_speed = (a[risky, None] for a in announced)
        lane = np.concatenate([np.repeat(lanes, band.size, axis=1), kept_lane], axis=1)
        speed = np.concatenate([np.tile(band, (risky.size, lanes.shape[1])), kept_speed], axis=1)
        flights = self._flights(robots, _Backups(risky, lane, speed, *_free(speed)), dt_s)
        x, y = robots.positions[0, risky, None], robots.positions[1, risky, None]
        heading = self._steer(x, y, robots.l_m[risky, None], lane, robots.speed[risky, None])
        deviation = np.hypot(
            speed * np.cos(heading) - (law_speed * np.cos(law_heading))[risky, None],
            speed * np.sin(heading) - (law_speed * np.sin(law_heading))[risky, None],
        )
        picked = np.arange(risky.size)
        best = self._best(robots, risky, flights, others, neighbours, dt_s, None, deviation)
        ahead = (robots.l_m[neighbours[risky]] > robots.l_m[risky, None]).astype(np.intp)  # (R, M): 1 ahead
        for _ in range(PASSES - 1):
            views = []  # column 0: every robot's announcement; 1: the same with the risky robots' fresh choices
            for (ox, oy), (fx, fy, _, _) in zip(others, flights):
                nx, ny = ox.copy(), oy.copy()
                nx[risky, 0], ny[risky, 0] = fx[picked, best], fy[picked, best]
                views.append((np.hstack([ox, nx]), np.hstack([oy, ny])))
            best = self._best(robots, risky, flights, views, neighbours, dt_s, ahead, deviation)
        return lane[picked, best], speed[picked, best]

    def _best(
        self,
        robots: _Robots,
        risky: IntArray,
        flights: list[Flight],
        others: list[tuple[FloatArray, FloatArray]],
        neighbours: IntArray,
        dt_s: float,
        seen: IntArray | None,
        deviation: FloatArray,
    ) -> IntArray:
        """The column of each risky robot's best backup among ``flights``: the safe one whose first command is
        closest to the law's (``deviation``), else the one whose first contact comes latest, then whose first
        shortfall, then the least short; the backup a robot announced (the last column) kept over a barely better
        one (`KEEP_M_S`, `KEEP_MPS`)."""
        first, contact, shortfall = self._foresee(robots, risky, flights, others, neighbours, dt_s, seen=seen)
        touch = np.where(np.isinf(contact), 0.0, self.horizon_s + 1.0 - contact)  # 0: none; the sooner the worse
        later = np.where(np.isinf(first), 0.0, self.horizon_s + 1.0 - first)  # 0: safe; else the sooner the worse
        score = 1e6 * touch + 1e4 * later + 1e2 * shortfall + deviation
        score[:, -1] -= np.where(later[:, -1] > 0.0, 1e2 * KEEP_M_S, KEEP_MPS)
        best: IntArray = np.argmin(score, axis=1)
        return best


def _free(like: FloatArray) -> tuple[FloatArray, FloatArray]:
    """No given first target: the backup steers for its lane from the first period on."""
    return np.full(like.shape, np.nan), np.full(like.shape, np.nan)


def _closest_squared(dx0: FloatArray, dy0: FloatArray, dx1: FloatArray, dy1: FloatArray) -> FloatArray:
    """The square of the closest two robots come over a step whose start and end separations are (dx0, dy0) and
    (dx1, dy1), both moving straight at constant speed over it: a crossing between two predicted points is not
    missed."""
    ex, ey = dx1 - dx0, dy1 - dy0  # written in place from here on: the same operations, fewer arrays
    t, work = dx0 * ex, dy0 * ey
    t += work
    np.negative(t, out=t)
    squared: FloatArray = np.multiply(ex, ex)
    squared += np.multiply(ey, ey, out=work)
    t /= np.maximum(squared, 1e-300, out=squared)
    t = np.minimum(np.maximum(t, 0.0, out=t), 1.0, out=t)
    cx = np.multiply(t, ex, out=ex)
    cx += dx0
    cy = np.multiply(t, ey, out=ey)
    cy += dy0
    np.multiply(cx, cx, out=squared)
    squared += np.multiply(cy, cy, out=work)
    return squared
