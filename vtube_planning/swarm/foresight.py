"""Foresight: the safety layer of a speed- and acceleration-limited swarm (``docs/theory.md`` §11).

A robot of the paper's model (1)-(4) cannot stop (v >= v_min) and changes its velocity slowly (a_v, a_n), so the
law's command (s1), which assumes a velocity that changes at once, can be a command the robot cannot fly in time:
flown under (3), (4) every mode collided and left the tube. The foresight keeps the law where the law is safe and
overrides it where it is not. Every period, for every robot:

1. the law's command is taken as a *target* (speed and heading) that the robot follows under (3), (4)
   (`vtube_planning.swarm.dynamics.respond`, the simulator's own physics) for a horizon T;
2. its predicted path is checked against the walls (clearance >= r_s inside the tube's span) and against every
   neighbour's predicted path (distance >= 2 r_s), the neighbours following the targets they chose the period
   before (each robot announces its target: the intent);
3. if the path is safe the law's target stands; else the robot chooses among targets around it (headings and
   speeds across the band) the safe one closest to the law's command, or, when none is safe, the one whose first
   unsafe moment is latest;
4. the robot is commanded its velocity after one period of following the chosen target: a command inside
   (2)-(4) from its current velocity.

Predicted points are located on the tube through tables of its centre line, tangent angle and half-width on a
fine grid, with one Newton step from the arc length the path's along-tube speed predicts: no projection search.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.params import SwarmParams
from vtube_planning.swarm.dynamics import respond

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]

LAW_OFFSETS = np.radians([0.0, 15.0, -15.0, 35.0, -35.0, 60.0, -60.0])
"""The targets' headings relative to the law's command, ..."""
OWN_OFFSETS = np.radians([0.0, 10.0, -10.0, 25.0, -25.0])
"""... and relative to the robot's own heading, each at v_min, mid-band and v_max."""
SUB_STEPS = 7
"""The horizon after the first period is predicted in this many equal steps."""
LOCATE_STEPS = 3
"""Newton steps of :meth:`TubeTables.locate` (from a guess a metre off, the offset is then within a millimetre)."""
TABLE_STEP_M = 0.05
"""Spacing of the tube's tables (m)."""
MAX_FROM_TANGENT = math.radians(80.0)
"""Targets pointing further than this from the tube's tangent are never chosen (the law's own command excepted)."""
ALL_PAIRS_UP_TO = 64
"""Swarms of up to this many robots check every neighbour; larger ones the nearest :data:`NEIGHBOURS`."""
NEIGHBOURS = 10
DECIDE_EVERY_S = 0.0
"""How often the foresight decides (s; 0: every period): in between, a robot keeps the target that replaced its
law's command at the last decision, and the others follow the law."""


@dataclass(frozen=True)
class TubeTables:
    """The tube on a fine grid, past both ends by ``margin_m``: where a predicted point lies, without searching."""

    l_m: FloatArray
    xy_m: FloatArray
    angle_rad: FloatArray
    curvature_per_m: FloatArray
    half_width_m: FloatArray
    length_m: float

    @classmethod
    def of(cls, tube: VirtualTube, margin_m: float) -> TubeTables:
        """Tables of ``tube`` from -``margin_m`` to L + ``margin_m``."""
        count = math.ceil((tube.length_m + 2 * margin_m) / TABLE_STEP_M) + 1
        l_m = np.linspace(-margin_m, tube.length_m + margin_m, count)
        tangent = tube.tangent(l_m)
        angle = np.unwrap(np.arctan2(tangent[:, 1], tangent[:, 0]))
        curvature = np.asarray(tube.curvature(l_m), dtype=float)
        return cls(l_m, tube.center_at(l_m).T.copy(), angle, curvature, np.asarray(tube.half_width(l_m)), tube.length_m)

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


def default_horizon(swarm: SwarmParams) -> float:
    """The foresight's horizon T when none is given: (v_max - v_min) / a_v, the time the largest speed change
    takes, and at least 1 s (s)."""
    return max(1.0, (swarm.v_max_mps - swarm.v_min_mps) / swarm.a_v_mps2)


class Foresight:
    """The foresight of a swarm of ``n_robots``, with its state (every robot's announced target).

    ``horizon_s`` is T (:func:`default_horizon` is the usual choice). With ``acceleration_limits`` the robots
    obey (3), (4); without, a velocity changes at once (the paper's model) and the foresight predicts that.
    """

    def __init__(
        self,
        tube: VirtualTube,
        swarm: SwarmParams,
        n_robots: int,
        *,
        horizon_s: float,
        acceleration_limits: bool,
        decide_every_s: float = DECIDE_EVERY_S,
    ) -> None:
        self.swarm = swarm
        self.decide_every_s = decide_every_s
        self.horizon_s = float(horizon_s)
        self.a_v = swarm.a_v_mps2 if acceleration_limits else math.inf
        self.a_n = swarm.a_n_mps2 if acceleration_limits else math.inf
        self.tables = TubeTables.of(tube, swarm.v_max_mps * self.horizon_s + 2.0 * swarm.r_a_m)
        self.intent: tuple[FloatArray, FloatArray] | None = None
        self.held: tuple[NDArray[np.bool_], FloatArray, FloatArray] = (
            np.zeros(n_robots, dtype=bool),
            np.zeros(n_robots),
            np.zeros(n_robots),
        )  # the robots whose law's command was replaced at the last decision, and their targets
        self._since = math.inf  # time since the last decision
        self.overridden = 0  # robot-decisions where the law's command was replaced

    def __call__(self, positions: FloatArray, velocity: FloatArray, command: FloatArray, dt_s: float) -> FloatArray:
        """The commands (2, N) for robots at ``positions`` flying ``velocity`` whose law commands ``command``."""
        speed, heading = np.hypot(velocity[0], velocity[1]), np.arctan2(velocity[1], velocity[0])
        law_speed = np.clip(np.hypot(command[0], command[1]), self.swarm.v_min_mps, self.swarm.v_max_mps)
        law_heading = np.arctan2(command[1], command[0])
        self._since += dt_s
        if self._since >= self.decide_every_s - 1e-9:
            self._since = 0.0
            self._decide(positions, speed, heading, law_speed, law_heading, dt_s)
        held, held_speed, held_heading = self.held
        target_speed = np.where(held, held_speed, law_speed)
        target_heading = np.where(held, held_heading, law_heading)
        self.intent = (target_speed, target_heading)
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
    ) -> None:
        """Which robots' law commands are unsafe over the horizon, and the targets that replace them."""
        l_m = self.tables.locate(positions[0], positions[1], self._l_guess(positions))[0]
        state = _State(positions, speed, heading, l_m, np.arange(speed.size))
        if self.intent is None:
            self.intent = (speed.copy(), heading.copy())
        others = self._others(state, dt_s)
        neighbours = self._neighbours(positions)
        first = self._foresee(state, law_speed[:, None], law_heading[:, None], others, neighbours, dt_s)[0][:, 0]
        risky = np.flatnonzero(np.isfinite(first))
        held = np.zeros(speed.size, dtype=bool)
        held_speed, held_heading = law_speed.copy(), law_heading.copy()
        if risky.size:
            held[risky] = True
            held_speed[risky], held_heading[risky] = self._choose(
                state, risky, law_speed, law_heading, others, neighbours, dt_s
            )
            self.overridden += risky.size
        self.held = (held, held_speed, held_heading)

    def _l_guess(self, positions: FloatArray) -> FloatArray:
        """A first arc length of every robot: the nearest table point."""
        tree = getattr(self, '_tree', None)
        if tree is None:
            tree = self._tree = cKDTree(self.tables.xy_m.T)
        return np.asarray(self.tables.l_m[tree.query(positions.T)[1]], dtype=float)

    def _times(self, dt_s: float) -> FloatArray:
        """The step lengths of a prediction: one period, then :data:`SUB_STEPS` equal steps to the horizon."""
        rest = max(self.horizon_s - dt_s, dt_s)
        return np.concatenate([[dt_s], np.full(SUB_STEPS, rest / SUB_STEPS)])

    def _others(self, state: _State, dt_s: float) -> list[tuple[FloatArray, FloatArray]]:
        """Every robot's predicted position at each step of the horizon, following its announced target."""
        assert self.intent is not None
        speed, heading = state.speed, state.heading
        x, y = state.positions[0], state.positions[1]
        path = []
        for step in self._times(dt_s):
            speed, heading = respond(speed, heading, self.intent[0], self.intent[1], self.a_v, self.a_n, step)
            x, y = x + step * speed * np.cos(heading), y + step * speed * np.sin(heading)
            path.append((x, y))
        return path

    def _neighbours(self, positions: FloatArray) -> IntArray:
        """(N, M) indices of the robots each robot checks (itself as padding where it has fewer)."""
        n = positions.shape[1]
        if n <= ALL_PAIRS_UP_TO:
            return np.tile(np.arange(n), (n, 1))
        return np.asarray(cKDTree(positions.T).query(positions.T, k=min(n, NEIGHBOURS + 1))[1], dtype=np.intp)

    def _foresee(
        self,
        state: _State,
        target_speed: FloatArray,
        target_heading: FloatArray,
        others: list[tuple[FloatArray, FloatArray]],
        neighbours: IntArray,
        dt_s: float,
    ) -> tuple[FloatArray, FloatArray]:
        """(R, K) how far robots ``state.rows`` following targets (R, K) fall short of the safe distances over the
        horizon: the integral over time of (r_s - clearance)+ and (2 r_s - the nearest neighbour's distance)+, m s;
        0 where the whole predicted path keeps them), and the time of the first step that falls short (inf: none)."""
        rows = state.rows
        r_s = self.swarm.r_s_m
        speed = np.broadcast_to(state.speed[rows, None], target_speed.shape)
        heading = np.broadcast_to(state.heading[rows, None], target_speed.shape)
        x, y = state.positions[0, rows, None], state.positions[1, rows, None]
        l_m = np.broadcast_to(state.l_m[rows, None], target_speed.shape)
        near = neighbours[rows]  # (R, M)
        itself = np.broadcast_to((near == rows[:, None])[:, None, :], (*target_speed.shape, near.shape[1]))
        shortfall = np.zeros(target_speed.shape)
        first = np.full(target_speed.shape, np.inf)
        elapsed = 0.0
        for step, (ox, oy) in zip(self._times(dt_s), others):
            elapsed += step
            speed, heading = respond(speed, heading, target_speed, target_heading, self.a_v, self.a_n, step)
            dx, dy = step * speed * np.cos(heading), step * speed * np.sin(heading)
            x, y = x + dx, y + dy
            l_m, offset = self.tables.locate(x, y, l_m + np.hypot(dx, dy))
            wall = np.maximum(r_s - self.tables.clearance(l_m, offset), 0.0)
            gap = np.hypot(x[:, :, None] - ox[near][:, None, :], y[:, :, None] - oy[near][:, None, :])
            gap[itself] = np.inf
            short = wall + np.maximum(2.0 * r_s - gap.min(axis=2), 0.0)
            shortfall += step * short
            first[(short > 0.0) & np.isinf(first)] = elapsed
        return first, shortfall

    def _choose(
        self,
        state: _State,
        risky: IntArray,
        law_speed: FloatArray,
        law_heading: FloatArray,
        others: list[tuple[FloatArray, FloatArray]],
        neighbours: IntArray,
        dt_s: float,
    ) -> tuple[FloatArray, FloatArray]:
        """The targets of the ``risky`` robots: the safe one closest to the law's command, else the one that falls
        least short."""
        band = np.array(
            [self.swarm.v_min_mps, 0.5 * (self.swarm.v_min_mps + self.swarm.v_max_mps), self.swarm.v_max_mps]
        )
        headings = np.concatenate(
            [law_heading[risky, None] + LAW_OFFSETS, state.heading[risky, None] + OWN_OFFSETS], axis=1
        )
        heading = np.repeat(headings, band.size, axis=1)
        speed = np.tile(band, (risky.size, headings.shape[1]))
        first, shortfall = self._foresee(state.of(risky), speed, heading, others, neighbours, dt_s)
        deviation = np.hypot(
            speed * np.cos(heading) - (law_speed * np.cos(law_heading))[risky, None],
            speed * np.sin(heading) - (law_speed * np.sin(law_heading))[risky, None],
        )
        tangent = np.interp(state.l_m[risky], self.tables.l_m, self.tables.angle_rad)
        backwards = np.cos(heading - tangent[:, None]) < math.cos(MAX_FROM_TANGENT)
        later = np.where(np.isinf(first), 0.0, self.horizon_s + 1.0 - first)  # 0: safe; else the sooner the worse
        score = 1e4 * later + 1e2 * shortfall + deviation + 1e6 * backwards
        best = np.argmin(score, axis=1)
        rows = np.arange(risky.size)
        return speed[rows, best], heading[rows, best]


@dataclass(frozen=True)
class _State:
    """The robots now (positions (2, N), speeds, headings, arc lengths (N,)), and the ones a prediction is for."""

    positions: FloatArray
    speed: FloatArray
    heading: FloatArray
    l_m: FloatArray
    rows: IntArray

    def of(self, rows: IntArray) -> _State:
        """The same robots, predicting for ``rows`` only."""
        return _State(self.positions, self.speed, self.heading, self.l_m, rows)
