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
(`vtube_planning.swarm.tube_tables`), by Newton steps from the arc length the path predicts. The predictions are
flown and checked compiled (`vtube_planning.swarm.foresight_kernel`); this module decides.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.params import ControlParams, SwarmParams
from vtube_planning.swarm.dynamics import respond

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]

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
ALL_CORES_FROM = 5000
"""Swarms of this many robots and more are predicted on all cores (numba's threads; the same bits): below it a
period's predictions are too short to share (a thread waits for its turn on a busy core longer than it works)."""
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
    """The robots now: positions (2, N), speeds, headings, arc lengths and lanes (N,)."""

    positions: FloatArray
    speed: FloatArray
    heading: FloatArray
    l_m: FloatArray
    lane: FloatArray

    @cached_property
    def packed(self) -> FloatArray:
        """(5, N): x, y, speed, heading and arc length, as `foresight_kernel.flights` reads them."""
        return np.vstack([self.positions, self.speed, self.heading, self.l_m])


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
        # numba (the compiled tables and predictions) is imported here, where a foresight flies: it takes 0.4 s
        from vtube_planning.swarm.tube_tables import TubeTables

        self.swarm = swarm
        self.horizon_s = float(horizon_s)
        self.a_v = swarm.a_v_mps2 if acceleration_limits else math.inf
        self.a_n = swarm.a_n_mps2 if acceleration_limits else math.inf
        window = merge_window(swarm) if acceleration_limits else 0.0
        self.tables = TubeTables.of(tube, swarm.v_max_mps * self.horizon_s + 2.0 * swarm.r_a_m, window)
        limits = [self.a_v, self.a_n, swarm.r_s_m, LANE_LOOKAHEAD_S, PREDICTION_LOCATE_STEPS]
        self._limits = np.array(limits, dtype=float)  # as `foresight_kernel.flights` reads them
        self.announced: tuple[FloatArray, FloatArray] | None = None  # every robot's lane and speed
        self.overridden = 0  # robot-periods where the law's command was replaced
        self._held: FloatArray | float = 0.0  # per robot, how much longer it flies a backup before the law again
        self._steps: tuple[float, FloatArray] = (math.nan, np.empty(0))  # the last period's `_times`
        self._all_pairs: IntArray = np.empty((0, 0), dtype=np.intp)  # the last swarm's `_neighbours`, all pairs

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
        guess = self.tables.nearest_l(positions, all_cores=speed.size >= ALL_CORES_FROM)
        l_m, offset = self.tables.locate(positions[0], positions[1], guess)
        lane = self.tables.lane_of(l_m, offset, self.swarm.r_s_m)
        robots = _Robots(positions, speed, heading, l_m, lane)
        announced = self.announced if self.announced is not None else (lane, speed)
        rows, free = np.arange(speed.size), np.full(speed.size, np.nan)
        both = _Backups(  # column 0: the backup each announced (its neighbours' view), 1: its law's command
            rows,
            _columns(announced[0], lane),
            _columns(announced[1], law_speed),
            _columns(free, law_speed),
            _columns(free, law_heading),
        )
        flights = self._flights(robots, both, dt_s)
        others = np.ascontiguousarray(flights[:2, :, :, :1])
        neighbours = self._neighbours(positions)
        law = np.ascontiguousarray(flights[:, :, :, 1:])
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
        if self._steps[0] != dt_s:
            rest = max(self.horizon_s - dt_s, dt_s)
            self._steps = (dt_s, np.concatenate([[dt_s], np.full(SUB_STEPS, rest / SUB_STEPS)]))
        return self._steps[1]

    def _flights(self, robots: _Robots, backups: _Backups, dt_s: float) -> FloatArray:
        """(4, S, R, K): x, y, arc length l and offset y_tube at the end of each step of robots ``backups.rows``
        flying their backups (R, K) (`foresight_kernel.flights`). Over the first step, one period, a robot moves at
        its new velocity, as the simulator moves it; over a longer step its velocity changes linearly while (3), (4)
        let it (`foresight_kernel.changing`), then holds (moved at the new velocity over a long step instead, a
        robot braking at a_v would fall short by a_v step^2 / 2: 9 cm in 0.43 s at 1 m/s^2)."""
        from vtube_planning.swarm.foresight_kernel import flights, parallel_flights  # numba: see __init__

        first = np.stack([backups.first_speed, backups.first_heading])
        fly = parallel_flights if robots.speed.size >= ALL_CORES_FROM else flights
        flown: FloatArray = fly(
            robots.packed,
            backups.rows,
            np.ascontiguousarray(backups.lane, dtype=float),
            np.ascontiguousarray(backups.speed, dtype=float),
            first,
            self._times(dt_s),
            self.tables.compiled,
            self._limits,
        )
        return flown

    def _neighbours(self, positions: FloatArray) -> IntArray:
        """(N, M) indices of the robots each robot checks (itself as padding where it has fewer)."""
        n = positions.shape[1]
        if n <= ALL_PAIRS_UP_TO:
            if self._all_pairs.shape[0] != n:
                self._all_pairs = np.tile(np.arange(n), (n, 1))
            return self._all_pairs
        from vtube_planning.swarm.nearest import nearest  # numba: see __init__

        x, y = np.ascontiguousarray(positions, dtype=float)
        return nearest(x, y, x, y, min(n, NEIGHBOURS + 1), all_cores=n >= ALL_CORES_FROM)

    def _foresee(
        self,
        robots: _Robots,
        rows: IntArray,
        flights: FloatArray,
        others: FloatArray,
        neighbours: IntArray,
        dt_s: float,
        margin_m: float = 0.0,
        seen: IntArray | None = None,
    ) -> FloatArray:
        """(3, R, K) for robots ``rows`` flying ``flights`` (`_flights`) among their neighbours flying ``others``
        (2, S, N, C), each neighbour seen in its flight ``seen`` (R, M; default the first): the time of the first
        step closer than r_s to a wall or 2 r_s to a neighbour (inf: none), the time of the first contact (a centre
        outside the tube, or bodies closer than 2 r_p), and how far short they fall over the horizon, the integral
        over time of (r_s - clearance)+ and (2 r_s - the nearest neighbour's distance)+ (m s); ``margin_m`` added to
        r_s and 2 r_s (`foresight_kernel.foresee`)."""
        from vtube_planning.swarm.foresight_kernel import foresee, parallel_foresee  # numba: see __init__

        near = np.ascontiguousarray(neighbours[rows])
        view = np.zeros_like(near) if seen is None else np.ascontiguousarray(seen, dtype=np.intp)
        swarm = self.swarm
        bounds = np.array([swarm.r_s_m, swarm.r_p_m, margin_m, self.tables.length_m], dtype=float)
        check = parallel_foresee if robots.speed.size >= ALL_CORES_FROM else foresee
        found: FloatArray = check(
            flights,
            others,
            robots.packed,
            rows,
            near,
            view,
            self._times(dt_s),
            self.tables.compiled,
            bounds,
        )
        return found

    def _choose(
        self,
        robots: _Robots,
        risky: IntArray,
        law_speed: FloatArray,
        law_heading: FloatArray,
        announced: tuple[FloatArray, FloatArray],
        others: FloatArray,
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
            fresh = others.copy()  # every robot's announcement, with the risky robots' fresh choices
            fresh[:, :, risky, 0] = flights[:2, :, picked, best]
            views = np.concatenate([others, fresh], axis=3)  # seen: 0 the announcement, 1 the fresh choice
            best = self._best(robots, risky, flights, views, neighbours, dt_s, ahead, deviation)
        return lane[picked, best], speed[picked, best]

    def _best(
        self,
        robots: _Robots,
        risky: IntArray,
        flights: FloatArray,
        others: FloatArray,
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


def _columns(first: FloatArray, second: FloatArray) -> FloatArray:
    """(N, 2): two (N,) arrays side by side (np.column_stack, with less to do)."""
    both = np.empty((first.size, 2))
    both[:, 0], both[:, 1] = first, second
    return both


def _free(like: FloatArray) -> tuple[FloatArray, FloatArray]:
    """No given first target: the backup steers for its lane from the first period on."""
    return np.full(like.shape, np.nan), np.full(like.shape, np.nan)
