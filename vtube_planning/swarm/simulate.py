"""The paper's numerical study: a speed-constrained single-integrator swarm flying through a virtual tube.

Each robot integrates p' = v_c (eq. 1), its command saturated into [v_min, v_max] (eq. 2) by the controller: the
paper's model. Optionally (``acceleration_limits``) every robot also obeys the tangential and normal acceleration
limits (3), (4): its speed changes by at most a_v per second and its heading turns at most at a_n / |v|. With
Table 1 that is a turning radius of 4 m at v_min and 25 m at v_max, too wide for the robots to follow their
avoidance commands in the paper's tubes: planned or not, robots then leave the tube (measured on scenes A-D), so
the paper's study cannot have applied (3), (4) per robot; the planner applies them to the swarm's average motion.

The swarm starts in a grid before the entrance (spacing 2 r_a, as many columns as fit the entrance with r_a to
spare, rows behind), moving along the tube at the plan's initial speed; the run ends when every robot has passed
l = L, or at the time limit.

*With planning* the forward term follows the plan and the avoidance radius follows (a3); *without planning* the
forward speed is a constant and r_a keeps its initial value: the paper's comparison. The constant defaults to
the middle of the speed range, (v_min + v_max) / 2, the convention of the group's code (``docs/theory.md`` §2.7-2.8:
TCNS 2 m/s in [0.5, 3.5], Robotarium k1 = v_max / 2).
"""

from __future__ import annotations

import math
import os
import time
from collections import deque
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vtube_planning._validate import is_positive, is_real
from vtube_planning.errors import ParamsError, PlanError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.onboard import PlanProfile, Projection, SwarmStep, swarm_density
from vtube_planning.params import SwarmParams
from vtube_planning.planning.plan import Plan
from vtube_planning.planning.planner import SwarmState, replan
from vtube_planning.swarm.control import ControlParams
from vtube_planning.swarm.log import LogWriter
from vtube_planning.swarm.metrics import PassageMetrics, passage_metrics

FloatArray = NDArray[np.float64]


FAILURE_MODES = ('stop', 'coast')


@dataclass(frozen=True)
class RobotFailure:
    """Robot ``robot`` fails once its arc length reaches ``at_m``: it stops dead (``'stop'``) or keeps the velocity
    it had (``'coast'``), whatever it is commanded; the others see it and must avoid it."""

    robot: int
    at_m: float
    mode: str = 'stop'

    def __post_init__(self) -> None:
        if isinstance(self.robot, bool) or not isinstance(self.robot, int) or self.robot < 0:
            msg = f'the failing robot must be a robot index >= 0; got {self.robot!r}.'
            raise ParamsError(msg)
        if not is_real(self.at_m):
            msg = f'the failure arc length at_m must be a finite number; got {self.at_m!r}.'
            raise ParamsError(msg)
        if self.mode not in FAILURE_MODES:
            msg = f'failure mode must be one of {FAILURE_MODES}; got {self.mode!r}.'
            raise ParamsError(msg)


@dataclass(frozen=True)
class SimConfig:
    """How a simulation runs.

    Parameters
    ----------
    dt_s
        Integration and control step, > 0.
    time_limit_s
        Stop here if some robot has not passed the exit; None means 4 (L + formation length) / v_min.
    seed
        Seed of every draw: the initial formation's jitter, and the faults' noise and message losses (each its own
        stream, so switching a fault on leaves the formation unchanged).
    jitter_m
        Standard deviation of the initial positions around the grid, m (0 for a perfect grid).
    log_every
        Steps between rewrites of the log file.
    acceleration_limits
        Make every robot obey the tangential and normal acceleration limits (3), (4). Off by default: each robot
        moves at its saturated command, as in the paper's model.
    pose_noise_m
        Fault: the controller sees every position with Gaussian noise of this standard deviation (m, per axis, drawn
        anew each step from a stream seeded by ``seed``); the metrics use the true positions. 0: off.
    latency_steps
        Fault: a command reaches the robots this many control periods after it was computed (until then they
        keep their initial velocity). 0: off.
    failure
        Fault: a robot that fails at an arc length (:class:`RobotFailure`); None: off. Once failed it no longer
        counts for the passage (the run ends, and the passing time is taken, when the working robots have passed)
        nor for tube violations, and it still counts for distances and collisions: the others must avoid it.
    dropout
        Fault: each control period each robot's message is lost with this probability (seeded): its neighbours
        then avoid it where they last heard it. 0: off. The planned controller only (the baselines hear everyone).
    replan_every_s
        Replan the rest of the tube this often (rounded to whole control periods) from the swarm's measured state,
        :func:`~vtube_planning.planning.planner.replan`: the working robots' mean arc length and forward speed,
        the measured density, and their number. Each call's wall time is kept (``SimResult.meta['replans']``).
        0: fly the first plan throughout. Planned flights only.
    """

    dt_s: float = 0.02
    time_limit_s: float | None = None
    seed: int = 0
    jitter_m: float = 0.05
    log_every: int = 100
    acceleration_limits: bool = False
    pose_noise_m: float = 0.0
    latency_steps: int = 0
    failure: RobotFailure | None = None
    dropout: float = 0.0
    replan_every_s: float = 0.0

    def __post_init__(self) -> None:
        if not is_positive(self.dt_s):
            msg = f'simulation dt_s must be a finite number > 0; got {self.dt_s!r}.'
            raise ParamsError(msg)
        if self.time_limit_s is not None and not is_positive(self.time_limit_s):
            msg = f'simulation time_limit_s must be > 0 or omitted; got {self.time_limit_s!r}.'
            raise ParamsError(msg)
        if not (isinstance(self.jitter_m, (int, float)) and self.jitter_m >= 0):
            msg = f'simulation jitter_m must be >= 0; got {self.jitter_m!r}.'
            raise ParamsError(msg)
        if not (is_real(self.pose_noise_m) and self.pose_noise_m >= 0):
            msg = f'simulation pose_noise_m must be a finite number >= 0 (0: no noise); got {self.pose_noise_m!r}.'
            raise ParamsError(msg)
        if not (is_real(self.dropout) and 0.0 <= self.dropout < 1.0):
            msg = (
                f'simulation dropout must be a probability in [0, 1) (0: every message arrives); got {self.dropout!r}.'
            )
            raise ParamsError(msg)
        if not (is_real(self.replan_every_s) and self.replan_every_s >= 0):
            msg = f'simulation replan_every_s must be a finite number >= 0 (0: never); got {self.replan_every_s!r}.'
            raise ParamsError(msg)
        if isinstance(self.latency_steps, bool) or not isinstance(self.latency_steps, int) or self.latency_steps < 0:
            msg = f'simulation latency_steps must be a whole number >= 0 (0: none); got {self.latency_steps!r}.'
            raise ParamsError(msg)


@dataclass(frozen=True)
class SimResult:
    """A simulated passage: per-step arrays and the metrics computed from them.

    Arrays have T rows (steps): ``t_s`` (T,), ``positions_m``, ``velocities_mps``, ``commands_mps`` (T, 2, N),
    ``r_a_m``, ``l_m``, ``clearance_m``, ``forward_speed_mps`` (T, N), ``density_per_m2`` (T,). ``flown`` is the
    plan as flown (the plan's profile, or :meth:`Replanner.flown` when it was replanned; None without a plan).
    """

    t_s: FloatArray
    positions_m: FloatArray
    velocities_mps: FloatArray
    commands_mps: FloatArray
    r_a_m: FloatArray
    l_m: FloatArray
    clearance_m: FloatArray
    forward_speed_mps: FloatArray
    density_per_m2: FloatArray
    metrics: PassageMetrics
    planned: bool
    meta: dict[str, Any] = field(default_factory=dict)
    flown: PlanProfile | None = None


def initial_formation(tube: VirtualTube, swarm: SwarmParams, rng: np.random.Generator, jitter_m: float) -> FloatArray:
    """Grid of N robots before the entrance, (2, N): spacing 2 r_a, front row r_a before l = 0."""
    spacing = 2.0 * swarm.r_a_m
    lam0 = float(tube.half_width(0.0))
    fit = math.floor(2.0 * (lam0 - swarm.r_a_m) / spacing) + 1
    if fit < 1:
        msg = (
            f'the entrance (half-width {lam0:g} m) is too narrow for one robot with its avoidance radius '
            f'r_a = {swarm.r_a_m:g} m; widen the tube or lower r_a_m.'
        )
        raise ParamsError(msg)
    cols = max(1, min(swarm.n_side, fit))
    rows = math.ceil(swarm.n_robots / cols)
    points = []
    for row in range(rows):
        in_row = min(cols, swarm.n_robots - row * cols)
        l_row = -swarm.r_a_m - spacing * row
        for c in range(in_row):
            y = (c - 0.5 * (in_row - 1)) * spacing
            points.append(tube.center_at(l_row) + y * tube.normal(l_row))
    positions = np.array(points).T
    return positions + jitter_m * rng.standard_normal(positions.shape)


def default_constant_speed(swarm: SwarmParams) -> float:
    """The forward speed of a swarm without planning: the middle of its speed range, m/s."""
    return 0.5 * (swarm.v_min_mps + swarm.v_max_mps)


def limit_acceleration(velocity: FloatArray, command: FloatArray, a_v: float, a_n: float, dt_s: float) -> FloatArray:
    """The velocity after one step of following ``command`` with |d|v|/dt| <= a_v and |v| |dtheta/dt| <= a_n."""
    speed = np.hypot(velocity[0], velocity[1])
    target = np.hypot(command[0], command[1])
    new_speed = speed + np.clip(target - speed, -a_v * dt_s, a_v * dt_s)
    heading = np.arctan2(velocity[1], velocity[0])
    turn = np.angle(np.exp(1j * (np.arctan2(command[1], command[0]) - heading)))
    max_turn = a_n * dt_s / np.maximum(new_speed, 1e-12)
    heading = heading + np.clip(turn, -max_turn, max_turn)
    return new_speed * np.vstack([np.cos(heading), np.sin(heading)])


LOGGED_FLOATS_PER_ROBOT = 10
"""Per robot and step the simulation keeps positions, velocities and commands (2 each), r_a, l, clearance and the
forward speed: 10 floats, twice while they are stacked into arrays."""


def available_memory_bytes() -> int | None:
    """The physical memory not in use now (None where the platform does not say)."""
    try:
        return int(os.sysconf('SC_AVPHYS_PAGES')) * int(os.sysconf('SC_PAGE_SIZE'))
    except (AttributeError, ValueError, OSError):
        return None


def _check_memory(steps: int, n: int, limit_s: float) -> None:
    """Refuse a run whose trajectory, kept to the time limit, would not fit the memory available."""
    need = 2 * steps * n * LOGGED_FLOATS_PER_ROBOT * 8
    free = available_memory_bytes()
    if free is not None and need > free:
        msg = (
            f'flying {n} robots for up to {limit_s:.0f} s (the time limit) keeps about {need / 2**30:.1f} GiB of '
            f'trajectory in memory, more than the {free / 2**30:.1f} GiB available; fly fewer robots, or set a '
            'shorter time_limit_s.'
        )
        raise ParamsError(msg)


class Replanner:
    """Replans a flight every ``every`` control periods from the swarm's measured state, and keeps the record."""

    def __init__(self, plan: Plan, tube: VirtualTube, every: int) -> None:
        self.plan, self.tube, self.every = plan, tube, every
        self.profiles = [plan.profile]
        self.calls: list[dict[str, Any]] = []

    def __call__(
        self, step: int, view: Projection, velocity: FloatArray, density: float, working: NDArray[np.bool_]
    ) -> PlanProfile | None:
        """The new plan's profile at a replanning step (None otherwise, or when replanning failed), from what the
        controller sees (``view``), the robots' velocities and the measured density."""
        if step == 0 or step % self.every:
            return None
        l_m = view.l_m
        flying = working & (l_m < self.tube.length_m)
        if not flying.any():
            return None
        forward_mps = np.einsum('ij,ij->j', velocity, view.tangent)
        start = max(0.0, float(l_m[flying].mean()))
        if start > self.tube.length_m - 2.0 * self.plan.options.grid_step_m:
            return None  # the swarm is leaving: nothing left to plan
        count = int(working.sum())
        state = SwarmState(start, float(forward_mps[flying].mean()), density, None if working.all() else count)
        started = time.perf_counter()
        try:
            rest = replan(self.plan, state, self.tube)
        except PlanError as err:
            self.calls.append({'step': step, 'from_m': start, 'wall_ms': _ms_since(started), 'error': str(err)})
            return None
        self.calls.append({'step': step, 'from_m': start, 'wall_ms': _ms_since(started), 'error': ''})
        self.profiles.append(rest.profile)
        return rest.profile

    def flown(self) -> PlanProfile:
        """The plan as flown: each replanned profile replaces the one before from the arc length it starts at."""
        l_m, slowness, density = self.profiles[0].l_m, self.profiles[0].slowness_spm, self.profiles[0].density_per_m2
        for later in self.profiles[1:]:
            keep = l_m < later.l_m[0]
            l_m = np.concatenate([l_m[keep], later.l_m])
            slowness = np.concatenate([slowness[keep], later.slowness_spm])
            density = np.concatenate([density[keep], later.density_per_m2])
        return PlanProfile(l_m, slowness, density)


def _ms_since(started: float) -> float:
    return 1e3 * (time.perf_counter() - started)


def simulate(
    tube: VirtualTube,
    swarm: SwarmParams,
    control: ControlParams,
    *,
    plan: Plan | None,
    config: SimConfig | None = None,
    constant_speed_mps: float | None = None,
    initial_speed_mps: float | None = None,
    log_path: str | Path | None = None,
    meta: dict[str, Any] | None = None,
    baseline: Callable[[FloatArray, FloatArray, Projection], FloatArray] | None = None,
    on_step: Callable[[float], None] | None = None,
) -> SimResult:
    """Fly the swarm through the tube.

    Parameters
    ----------
    plan
        The plan to track; None flies *without planning* (constant speed and avoidance radius).
    constant_speed_mps
        The forward speed without planning; defaults to (v_min + v_max) / 2.
    initial_speed_mps
        Speed of every robot at t = 0 (along the tube); defaults to the plan's v*(0), else v_min.
    log_path
        Write the trajectory here as it is computed (``.npz``, rewritten every ``config.log_every`` steps).
    meta
        Extra description stored in the log and the result (scene name, ...).
    baseline
        Another swarm law, ``baseline(positions, velocities, projection) -> commands`` (the paper's baselines,
        :mod:`vtube_planning.baselines.flocking`); with it, ``plan`` must be None and r_a stays constant.
    on_step
        Told the simulated time after every step (a progress bar).
    """
    config = config or SimConfig()
    step_params = control.step_params(swarm)
    if plan is not None and baseline is not None:
        msg = 'a baseline flies without a plan; pass plan=None with baseline.'
        raise ParamsError(msg)
    if plan is not None:
        plan.check_matches(tube, swarm)
    replanner = None
    if config.replan_every_s > 0:
        if plan is None:
            msg = 'replanning (replan_every_s) needs a plan to start from; pass a plan or set replan_every_s = 0.'
            raise ParamsError(msg)
        replanner = Replanner(plan, tube, max(1, round(config.replan_every_s / config.dt_s)))
    forward_const = default_constant_speed(swarm) if constant_speed_mps is None else float(constant_speed_mps)
    if plan is None and not swarm.v_min_mps <= forward_const <= swarm.v_max_mps:
        msg = f'constant_speed_mps = {forward_const} lies outside [v_min, v_max] = [{swarm.v_min_mps}, {swarm.v_max_mps}].'
        raise ParamsError(msg)
    rng = np.random.default_rng(config.seed)
    positions = initial_formation(tube, swarm, rng, config.jitter_m)
    n = positions.shape[1]
    start_speed = initial_speed_mps
    if start_speed is None:
        start_speed = float(plan.speed_mps[0]) if plan is not None else swarm.v_min_mps
    velocity = start_speed * tube.project(positions).tangent
    stepper = SwarmStep(
        tube, step_params, n, plan=plan.profile if plan is not None else None, constant_speed_mps=forward_const
    )
    extent = float(np.ptp(tube.project(positions).l_m))
    limit = config.time_limit_s or 4.0 * (tube.length_m + extent + 2 * swarm.r_a_m) / swarm.v_min_mps
    steps = math.ceil(limit / config.dt_s)
    _check_memory(steps + 1, n, limit)
    description = dict(
        meta or {},
        kind='simulation',
        planned=plan is not None,
        n_robots=n,
        dt_s=config.dt_s,
        seed=config.seed,
        swarm=asdict(swarm),
        control=asdict(control),
        length_m=tube.length_m,
        tube_hash=tube.fingerprint(),
    )
    log = LogWriter(log_path, description, flush_every=config.log_every)
    if baseline is not None and config.dropout > 0:
        msg = 'dropped messages (dropout) act on the planned controller; fly the baseline with dropout = 0.'
        raise ParamsError(msg)
    if config.failure is not None and config.failure.robot >= n:
        msg = f'the failing robot {config.failure.robot} does not exist: the swarm has robots 0..{n - 1}.'
        raise ParamsError(msg)
    noise = np.random.default_rng([config.seed, 1])  # own streams: the formation's jitter stays the same
    losses = np.random.default_rng([config.seed, 2])
    heard = positions.copy()  # where the robots last heard each other
    pending = deque([velocity] * config.latency_steps)  # commands computed, not yet applied
    failed_velocity = None  # the failed robot's velocity from the failure on
    working = np.ones(n, dtype=bool)  # robots that count for the passage
    for step in range(steps + 1):
        projection = tube.project(positions)  # the truth: logged and measured
        seen, view = positions, projection
        if config.pose_noise_m > 0:
            seen = positions + config.pose_noise_m * noise.standard_normal(positions.shape)
            view = tube.project(seen)
        if baseline is not None:
            commanded = baseline(seen, velocity, view)
            density, r_a = swarm_density(tube, view.l_m, swarm.r_a_m), stepper.r_a
        else:
            others = None
            if config.dropout > 0:
                arrived = losses.random(n) >= config.dropout
                heard[:, arrived] = seen[:, arrived]
                others = heard
            result = stepper(seen, config.dt_s, view, others)
            commanded, density, r_a = result.velocity, result.density_per_m2, result.r_a_m
            if replanner is not None:
                profile = replanner(step, view, velocity, float(density), working)
                if profile is not None:
                    stepper.plan = profile
        done = bool(np.all((projection.l_m > tube.length_m) | ~working))
        log.append(
            t_s=np.float64(step * config.dt_s),
            positions_m=positions,
            velocities_mps=velocity,
            commands_mps=commanded,
            r_a_m=r_a,
            l_m=projection.l_m,
            clearance_m=projection.clearance_m,
            forward_speed_mps=np.einsum('ij,ij->j', velocity, projection.tangent),
            density_per_m2=np.float64(density),
        )
        if on_step is not None:
            on_step(step * config.dt_s)
        if done or step == steps:
            break
        if pending:
            pending.append(commanded)
            commanded = pending.popleft()
        if config.acceleration_limits:
            velocity = limit_acceleration(velocity, commanded, swarm.a_v_mps2, swarm.a_n_mps2, config.dt_s)
        else:
            velocity = commanded
        failure = config.failure
        if failure is not None:
            if failed_velocity is None and projection.l_m[failure.robot] >= failure.at_m:
                failed_velocity = np.zeros(2) if failure.mode == 'stop' else velocity[:, failure.robot].copy()
                working[failure.robot] = False
            if failed_velocity is not None:
                velocity = velocity.copy()
                velocity[:, failure.robot] = failed_velocity
        positions = positions + config.dt_s * velocity
    arrays = log.arrays()
    flown = None if plan is None else plan.profile if replanner is None else replanner.flown()
    metrics = passage_metrics(
        arrays['t_s'],
        arrays['positions_m'],
        arrays['l_m'],
        arrays['clearance_m'],
        tube.length_m,
        collision_distance_m=2.0 * swarm.r_p_m,
        speed_band_mps=(swarm.v_min_mps, swarm.v_max_mps),
        commands_mps=arrays['commands_mps'],
        forward_speed_mps=arrays['forward_speed_mps'],
        density_per_m2=arrays['density_per_m2'],
        plan=flown,
        counted=working,
    )
    if replanner is not None:
        description['replans'] = replanner.calls
    log.flush(metrics=metrics.to_json(), finished=True)
    return SimResult(**arrays, metrics=metrics, planned=plan is not None, meta=description, flown=flown)
