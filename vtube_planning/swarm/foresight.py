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
   law's, or, when none is safe, the one that falls short latest (then least), and keeps flying backups for
   `HOLD_S` before the law again;
4. the robot is commanded its velocity after one period of following the target: a command inside (2)-(4) from
   its present velocity.

Every prediction follows the robot's response under (3), (4) (`vtube_planning.swarm.dynamics.respond`, the
simulator's own physics). Predicted points are located on the tube through tables of its centre line, tangent
angle, curvature and half-width on a fine grid, by Newton steps from the arc length the path predicts.
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

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]

LANES = np.array([-1.0, -0.5, 0.0, 0.5, 1.0])
"""The backups' lanes eta (besides the robot's present one), each at v_min, mid-band and v_max."""
LANE_LOOKAHEAD_S = 1.0
"""A backup steers for its lane at the point this many seconds of flight ahead (at least 1 m)."""
SUB_STEPS = 7
"""The horizon after the first period is predicted in this many equal steps."""
LOCATE_STEPS = 3
"""Newton steps of `TubeTables.locate` (from a guess a metre off, the offset is then within a millimetre)."""
TABLE_STEP_M = 0.05
"""Spacing of the tube's tables (m)."""
LAW_MARGIN_M = 0.1
"""The law's command stands only with this much room to spare beyond r_s and 2 r_s: the backups take over before
the safe distances are reached, not at them."""
HOLD_S = 1.0
"""A robot whose law's command was unsafe flies backups for this long before the law again: two robots that each
make the other's law unsafe would otherwise take turns, one period the law, the next a backup, and fly neither."""
ALL_PAIRS_UP_TO = 64
"""Swarms of up to this many robots check every neighbour; larger ones the nearest `NEIGHBOURS`."""
NEIGHBOURS = 10
"""How many nearest neighbours a robot of a larger swarm checks."""


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
class TubeTables:
    """The tube on a fine grid, past both ends by ``margin_m``: where a predicted point lies, without searching."""

    l_m: FloatArray
    xy_m: FloatArray
    angle_rad: FloatArray
    curvature_per_m: FloatArray
    half_width_m: FloatArray
    """The narrowest half-width over the window ahead of each l."""
    length_m: float

    @classmethod
    def of(cls, tube: VirtualTube, margin_m: float, window_m: float = 0.0) -> TubeTables:
        """Tables of ``tube`` from -``margin_m`` to L + ``margin_m``; the half-width at l is the narrowest one over
        [l, l + ``window_m``]."""
        count = math.ceil((tube.length_m + 2 * margin_m) / TABLE_STEP_M) + 1
        l_m = np.linspace(-margin_m, tube.length_m + margin_m, count)
        tangent = tube.tangent(l_m)
        angle = np.unwrap(np.arctan2(tangent[:, 1], tangent[:, 0]))
        curvature = np.asarray(tube.curvature(l_m), dtype=float)
        half_width = np.asarray(tube.half_width(l_m), dtype=float)
        window = max(1, round(window_m / TABLE_STEP_M))
        padded = np.concatenate([half_width, np.full(window - 1, half_width[-1])])
        narrowest = np.lib.stride_tricks.sliding_window_view(padded, window).min(axis=1)
        return cls(l_m, tube.center_at(l_m).T.copy(), angle, curvature, narrowest, tube.length_m)

    def locate(self, x: FloatArray, y: FloatArray, l_guess: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Arc length and lateral offset of points (x, y) near arc lengths ``l_guess``: Newton steps on
        (p - gamma(l)) . t(l) = 0, whose derivative is -(1 - kappa y) (``docs/theory.md`` §3.1)."""
        for _ in range(LOCATE_STEPS):
            dx = x - np.interp(l_guess, self.l_m, self.xy_m[0])
            dy = y - np.interp(l_guess, self.l_m, self.xy_m[1])
            angle = np.interp(l_guess, self.l_m, self.angle_rad)
            cos, sin = np.cos(angle), np.sin(angle)
            offset = dy * cos - dx * sin
            bend = 1.0 - np.interp(l_guess, self.l_m, self.curvature_per_m) * offset
            l_guess = l_guess + (dx * cos + dy * sin) / np.maximum(bend, 0.1)
        return l_guess, offset

    def clearance(self, l_m: FloatArray, offset_m: FloatArray) -> FloatArray:
        """lambda(l) - |y|, +inf outside the tube's span 0 <= l <= L (where no wall is measured)."""
        inside = (l_m >= 0.0) & (l_m <= self.length_m)
        return np.where(inside, np.interp(l_m, self.l_m, self.half_width_m) - np.abs(offset_m), np.inf)

    def lane_heading(
        self, x: FloatArray, y: FloatArray, l_m: FloatArray, lane: FloatArray, r_s_m: float, ahead_m: FloatArray
    ) -> FloatArray:
        """The heading from (x, y), at arc length l, to the point of the lane eta ``ahead_m`` metres further along
        the tube (pure pursuit: it turns into a narrowing or a bend before the robot gets there)."""
        there = l_m + ahead_m
        room = np.maximum(np.interp(there, self.l_m, self.half_width_m) - r_s_m, 0.0)
        angle = np.interp(there, self.l_m, self.angle_rad)
        lateral = lane * room
        goal_x = np.interp(there, self.l_m, self.xy_m[0]) - lateral * np.sin(angle)
        goal_y = np.interp(there, self.l_m, self.xy_m[1]) + lateral * np.cos(angle)
        heading: FloatArray = np.arctan2(goal_y - y, goal_x - x)
        return heading

    def lane_of(self, l_m: FloatArray, offset_m: FloatArray, r_s_m: float) -> FloatArray:
        """The lane eta a robot at (l, y) flies in now, in [-1, 1]."""
        room = np.maximum(np.interp(l_m, self.l_m, self.half_width_m) - r_s_m, 1e-9)
        return np.clip(offset_m / room, -1.0, 1.0)


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
        self._tree = cKDTree(self.tables.xy_m.T)
        self.announced: tuple[FloatArray, FloatArray] | None = None  # every robot's lane and speed
        self.overridden = 0  # robot-periods where the law's command was replaced
        self._held: FloatArray | float = 0.0  # per robot, how much longer it flies a backup before the law again

    def __call__(self, positions: FloatArray, velocity: FloatArray, command: FloatArray, dt_s: float) -> FloatArray:
        """The commands (2, N) for robots at ``positions`` flying ``velocity`` whose law commands ``command``."""
        speed, heading = np.hypot(velocity[0], velocity[1]), np.arctan2(velocity[1], velocity[0])
        l_guess = self.tables.l_m[self._tree.query(positions.T)[1]]
        l_m, offset = self.tables.locate(positions[0], positions[1], l_guess)
        lane = self.tables.lane_of(l_m, offset, self.swarm.r_s_m)
        robots = _Robots(positions, speed, heading, l_m, offset, lane)
        law_speed = np.clip(np.hypot(command[0], command[1]), self.swarm.v_min_mps, self.swarm.v_max_mps)
        law_heading = np.arctan2(command[1], command[0])
        if self.announced is None:
            self.announced = (lane, speed)
        lanes, speeds = self._column(self.announced)
        rows = np.arange(speed.size)
        others = self._paths(robots, _Backups(rows, lanes, speeds, *_free(speeds)), dt_s)
        neighbours = self._neighbours(positions)
        law = _Backups(rows, lane[:, None], law_speed[:, None], law_speed[:, None], law_heading[:, None])
        first = self._foresee(robots, law, others, neighbours, dt_s, LAW_MARGIN_M)[0][:, 0]
        target_speed, target_heading = law_speed.copy(), law_heading.copy()
        announced_lane, announced_speed = lane.copy(), law_speed.copy()
        unsafe = np.isfinite(first)
        self._held = np.where(unsafe, HOLD_S, np.maximum(self._held - dt_s, 0.0))
        risky = np.flatnonzero(unsafe | (self._held > 0.0))
        if risky.size:
            chosen_lane, chosen_speed = self._choose(robots, risky, law_speed, law_heading, others, neighbours, dt_s)
            announced_lane[risky], announced_speed[risky] = chosen_lane, chosen_speed
            target_speed[risky] = chosen_speed
            target_heading[risky] = self._steer(
                positions[0, risky], positions[1, risky], l_m[risky], chosen_lane, speed[risky]
            )
            self.overridden += risky.size
        self.announced = (announced_lane, announced_speed)
        new_speed, new_heading = respond(speed, heading, target_speed, target_heading, self.a_v, self.a_n, dt_s)
        commanded: FloatArray = new_speed * np.vstack([np.cos(new_heading), np.sin(new_heading)])
        return commanded

    @staticmethod
    def _column(pair: tuple[FloatArray, FloatArray]) -> tuple[FloatArray, FloatArray]:
        """Lanes and speeds (N,) as one backup per robot, (N, 1)."""
        return pair[0][:, None], pair[1][:, None]

    def _steer(self, x: FloatArray, y: FloatArray, l_m: FloatArray, lane: FloatArray, speed: FloatArray) -> FloatArray:
        """The heading that steers for ``lane`` from (x, y) at arc length l and ``speed``."""
        ahead = np.maximum(1.0, speed * LANE_LOOKAHEAD_S)
        return self.tables.lane_heading(x, y, l_m, lane, self.swarm.r_s_m, ahead)

    def _times(self, dt_s: float) -> FloatArray:
        """The step lengths of a prediction: one period, then `SUB_STEPS` equal steps to the horizon."""
        rest = max(self.horizon_s - dt_s, dt_s)
        return np.concatenate([[dt_s], np.full(SUB_STEPS, rest / SUB_STEPS)])

    def _paths(self, robots: _Robots, backups: _Backups, dt_s: float) -> list[tuple[FloatArray, FloatArray]]:
        """Where robots ``backups.rows`` are at each step of the horizon, flying their backups: (x, y) per step,
        each (R, K)."""
        return [(x, y) for x, y, _, _ in self._flights(robots, backups, dt_s)]

    def _flights(
        self, robots: _Robots, backups: _Backups, dt_s: float
    ) -> list[tuple[FloatArray, FloatArray, FloatArray, FloatArray]]:
        """Each step's (x, y, l, y_tube) of robots ``backups.rows`` flying their backups (R, K)."""
        rows, shape = backups.rows, backups.lane.shape
        speed = np.broadcast_to(robots.speed[rows, None], shape)
        heading = np.broadcast_to(robots.heading[rows, None], shape)
        x, y = robots.positions[0, rows, None], robots.positions[1, rows, None]
        l_m = np.broadcast_to(robots.l_m[rows, None], shape)
        offset = np.broadcast_to(robots.offset_m[rows, None], shape)
        out = []
        for index, step in enumerate(self._times(dt_s)):
            target = self._steer(x, y, l_m, backups.lane, speed)
            target_speed = backups.speed
            if index == 0:
                given = np.isfinite(backups.first_heading)
                target = np.where(given, backups.first_heading, target)
                target_speed = np.where(given, backups.first_speed, target_speed)
            speed, heading = respond(speed, heading, target_speed, target, self.a_v, self.a_n, step)
            dx, dy = step * speed * np.cos(heading), step * speed * np.sin(heading)
            x, y = x + dx, y + dy
            l_m, offset = self.tables.locate(x, y, l_m + np.hypot(dx, dy))
            out.append((x, y, l_m, offset))
        return out

    def _neighbours(self, positions: FloatArray) -> IntArray:
        """(N, M) indices of the robots each robot checks (itself as padding where it has fewer)."""
        n = positions.shape[1]
        if n <= ALL_PAIRS_UP_TO:
            return np.tile(np.arange(n), (n, 1))
        return np.asarray(cKDTree(positions.T).query(positions.T, k=min(n, NEIGHBOURS + 1))[1], dtype=np.intp)

    def _foresee(
        self,
        robots: _Robots,
        backups: _Backups,
        others: list[tuple[FloatArray, FloatArray]],
        neighbours: IntArray,
        dt_s: float,
        margin_m: float = 0.0,
    ) -> tuple[FloatArray, FloatArray]:
        """(R, K) for robots ``backups.rows`` flying their backups: the time of the first step closer than r_s to a
        wall or 2 r_s to a neighbour (inf: none), and how far short they fall over the horizon, the integral over
        time of (r_s - clearance)+ and (2 r_s - the nearest neighbour's distance)+ (m s)."""
        rows, shape, r_s = backups.rows, backups.lane.shape, self.swarm.r_s_m
        near = neighbours[rows]  # (R, M)
        itself = np.broadcast_to((near == rows[:, None])[:, None, :], (*shape, near.shape[1]))
        shortfall, first = np.zeros(shape), np.full(shape, np.inf)
        elapsed = 0.0
        flights = self._flights(robots, backups, dt_s)
        for step, (x, y, l_m, offset), (ox, oy) in zip(self._times(dt_s), flights, others):
            elapsed += step
            wall = np.maximum(r_s + margin_m - self.tables.clearance(l_m, offset), 0.0)
            gap = np.hypot(x[:, :, None] - ox[near, 0][:, None, :], y[:, :, None] - oy[near, 0][:, None, :])
            gap[itself] = np.inf
            short = wall + np.maximum(2.0 * r_s + margin_m - gap.min(axis=2), 0.0)
            shortfall += step * short
            first[(short > 0.0) & np.isinf(first)] = elapsed
        return first, shortfall

    def _choose(
        self,
        robots: _Robots,
        risky: IntArray,
        law_speed: FloatArray,
        law_heading: FloatArray,
        others: list[tuple[FloatArray, FloatArray]],
        neighbours: IntArray,
        dt_s: float,
    ) -> tuple[FloatArray, FloatArray]:
        """The backups (lanes, speeds) of the ``risky`` robots: the safe one whose first command is closest to the
        law's, else the one that falls short latest, then least."""
        swarm = self.swarm
        band = np.array([swarm.v_min_mps, 0.5 * (swarm.v_min_mps + swarm.v_max_mps), swarm.v_max_mps])
        lanes = np.concatenate([np.tile(LANES, (risky.size, 1)), robots.lane[risky, None]], axis=1)
        lane = np.repeat(lanes, band.size, axis=1)
        speed = np.tile(band, (risky.size, lanes.shape[1]))
        first, shortfall = self._foresee(robots, _Backups(risky, lane, speed, *_free(speed)), others, neighbours, dt_s)
        x, y = robots.positions[0, risky, None], robots.positions[1, risky, None]
        heading = self._steer(x, y, robots.l_m[risky, None], lane, robots.speed[risky, None])
        deviation = np.hypot(
            speed * np.cos(heading) - (law_speed * np.cos(law_heading))[risky, None],
            speed * np.sin(heading) - (law_speed * np.sin(law_heading))[risky, None],
        )
        later = np.where(np.isinf(first), 0.0, self.horizon_s + 1.0 - first)  # 0: safe; else the sooner the worse
        best = np.argmin(1e4 * later + 1e2 * shortfall + deviation, axis=1)
        picked = np.arange(risky.size)
        return lane[picked, best], speed[picked, best]


def _free(like: FloatArray) -> tuple[FloatArray, FloatArray]:
    """No given first target: the backup steers for its lane from the first period on."""
    return np.full(like.shape, np.nan), np.full(like.shape, np.nan)
