"""The paper's numerical study: a speed-constrained single-integrator swarm flying through a virtual tube.

Each robot integrates p' = v_c (eq. 1), its command saturated into [v_min, v_max] (eq. 2) by the controller: the
paper's model. Optionally (``acceleration_limits``) every robot also obeys the tangential and normal acceleration
limits (3), (4): its speed changes by at most a_v per second and its heading turns at most at a_n / |v|.

The swarm starts in a grid before the entrance (spacing 2 r_a, as many columns as fit the entrance with r_a to
spare, rows behind), or where ``SimConfig.initial_positions_m`` puts it, moving along the tube at the plan's initial speed; the run ends when every robot has passed
l = L, or at the time limit.

*With planning* the forward term follows the plan and the avoidance radius follows (a3); *without planning* the
forward speed is a constant, by default (v_min + v_max) / 2 (``docs/theory.md`` §2.7-2.8), and r_a keeps its
initial value: the paper's comparison. The faults are in `faults`, replanning in flight in `replanner`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vtube_planning._validate import is_positive, is_real
from vtube_planning.errors import ParamsError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.log import LogWriter
from vtube_planning.onboard import PlanProfile, Projection, SwarmStep
from vtube_planning.params import ControlParams, SwarmParams
from vtube_planning.planning.plan import Plan
from vtube_planning.swarm.dynamics import dynamics_violations
from vtube_planning.swarm.faults import Faults, RobotFailure
from vtube_planning.swarm.foresight import foresight_for
from vtube_planning.swarm.formation import Positions, as_positions, start_formation
from vtube_planning.swarm.memory import check_memory
from vtube_planning.swarm.metrics import PassageMetrics, passage_metrics
from vtube_planning.swarm.period import Baseline, SimulatedPeriod
from vtube_planning.swarm.replanner import Replanner

FloatArray = NDArray[np.float64]


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
    initial_positions_m
        Where the robots start, (2, N) (any array-like; kept as `Positions`), one column per robot of the
        swarm, as given (not jittered); None: the grid before the entrance.
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
    lag_s
        Fault: the command that reaches the robots acts through a first-order lag of this time constant (s; each
        period's velocity is the lag's mean over the period, so positions follow it exactly). 0: off.
    failure
        Fault: a robot that fails at an arc length ([`RobotFailure`][vtube_planning.swarm.faults.RobotFailure]); None:
        off. Once failed it no longer counts for the passage (the run ends, and the passing time is taken, when the
        working robots have passed) nor for tube violations, and it still counts for distances and collisions: the
        others must avoid it.
    dropout
        Fault: each control period each robot's message is lost with this probability (seeded): its neighbours
        then avoid it where they last heard it. 0: off. The planned controller only (the baselines hear everyone).
    replan_every_s
        Replan the rest of the tube this often (rounded to whole control periods) from the swarm's measured state,
        [`replan`][vtube_planning.planning.planner.replan]: the working robots' mean arc length and forward speed,
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
    lag_s: float = 0.0
    failure: RobotFailure | None = None
    dropout: float = 0.0
    replan_every_s: float = 0.0
    initial_positions_m: Positions | None = None

    def __post_init__(self) -> None:
        if self.initial_positions_m is not None:
            object.__setattr__(self, 'initial_positions_m', as_positions(self.initial_positions_m))
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
        if not (is_real(self.lag_s) and self.lag_s >= 0):
            msg = f'simulation lag_s must be a finite number >= 0 (0: no lag); got {self.lag_s!r}.'
            raise ParamsError(msg)
        if isinstance(self.latency_steps, bool) or not isinstance(self.latency_steps, int) or self.latency_steps < 0:
            msg = f'simulation latency_steps must be a whole number >= 0 (0: none); got {self.latency_steps!r}.'
            raise ParamsError(msg)


@dataclass(frozen=True)
class SimResult:
    """A simulated passage: per-step arrays and the metrics computed from them.

    Arrays have T rows (steps): ``t_s`` (T,), ``positions_m``, ``velocities_mps``, ``commands_mps`` (T, 2, N),
    ``r_a_m``, ``l_m``, ``clearance_m``, ``forward_speed_mps`` (T, N), ``density_per_m2`` (T,). ``flown`` is the
    plan as flown (the plan's profile, or `Replanner.flown` when it was replanned; None without a plan).
    ``dynamics_violations`` counts the robot-periods whose command a robot of the model (2)-(4) could not fly from
    its velocity (`vtube_planning.swarm.dynamics.dynamics_violations`).
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
    dynamics_violations: int = 0


def default_constant_speed(swarm: SwarmParams) -> float:
    """The forward speed of a swarm without planning: the middle of its speed range, m/s."""
    return 0.5 * (swarm.v_min_mps + swarm.v_max_mps)


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
    baseline: Baseline | None = None,
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
        Another swarm law (`vtube_planning.baselines.flocking`, ...); with it ``plan`` is None, r_a constant.
    on_step
        Told the simulated time after every step (a progress bar).
    """
    config = config or SimConfig()
    step_params = control.step_params(swarm)
    replanner = _replanner(tube, swarm, plan, config, baseline)
    forward_const = _constant_speed(swarm, plan, constant_speed_mps)
    positions = start_formation(tube, swarm, config.initial_positions_m, config.seed, config.jitter_m)
    n = positions.shape[1]
    velocity = _initial_speed(swarm, plan, initial_speed_mps) * tube.project(positions).tangent
    profile = plan.profile if plan is not None else None
    stepper = SwarmStep(tube, step_params, n, plan=profile, constant_speed_mps=forward_const, velocity=velocity)
    steps = _step_count(tube, swarm, config, positions)
    description = _description(tube, swarm, control, plan, config, n, meta)
    log = LogWriter(log_path, description, flush_every=config.log_every)
    faults = _faults(config, baseline, positions, velocity)
    foresight, limits = foresight_for(tube, swarm, control, config.acceleration_limits), config.acceleration_limits
    period = SimulatedPeriod(tube, swarm, config.dt_s, limits, stepper, baseline, replanner, faults, foresight)
    for step in range(steps + 1):
        projection = tube.project(positions)  # the truth: logged and measured
        commanded, density, r_a = period.command(step, positions, projection, velocity)
        done = bool(np.all((projection.l_m > tube.length_m) | ~faults.working))
        _log_step(log, step * config.dt_s, positions, velocity, commanded, r_a, projection, density)
        if on_step is not None:
            on_step(step * config.dt_s)
        if done or step == steps:
            break
        velocity = period.next_velocity(velocity, commanded, projection.l_m)
        positions = positions + config.dt_s * velocity
    return _result(log, description, tube, swarm, plan, replanner, faults.working, config.dt_s)


def _replanner(
    tube: VirtualTube, swarm: SwarmParams, plan: Plan | None, config: SimConfig, baseline: Baseline | None
) -> Replanner | None:
    """The flight's replanner (None when it does not replan), once the plan is checked against the run."""
    if plan is not None and baseline is not None:
        msg = 'a baseline flies without a plan; pass plan=None with baseline.'
        raise ParamsError(msg)
    if plan is not None:
        plan.check_matches(tube, swarm)
    if config.replan_every_s <= 0:
        return None
    if plan is None:
        msg = 'replanning (replan_every_s) needs a plan to start from; pass a plan or set replan_every_s = 0.'
        raise ParamsError(msg)
    return Replanner(plan, tube, max(1, round(config.replan_every_s / config.dt_s)))


def _constant_speed(swarm: SwarmParams, plan: Plan | None, constant_speed_mps: float | None) -> float:
    """The forward speed flown without a plan, checked against the speed band."""
    forward_const = default_constant_speed(swarm) if constant_speed_mps is None else float(constant_speed_mps)
    if plan is None and not swarm.v_min_mps <= forward_const <= swarm.v_max_mps:
        msg = f'constant_speed_mps = {forward_const} lies outside [v_min, v_max] = [{swarm.v_min_mps}, {swarm.v_max_mps}].'
        raise ParamsError(msg)
    return forward_const


def _initial_speed(swarm: SwarmParams, plan: Plan | None, initial_speed_mps: float | None) -> float:
    """Every robot's speed at t = 0: the given one, else the plan's v*(0), else v_min."""
    if initial_speed_mps is not None:
        return initial_speed_mps
    return float(plan.speed_mps[0]) if plan is not None else swarm.v_min_mps


def _faults(config: SimConfig, baseline: Baseline | None, positions: FloatArray, velocity: FloatArray) -> Faults:
    """The run's faults, from its settings, the initial positions and velocities;
    [`ParamsError`][vtube_planning.errors.ParamsError] for faults it cannot have (dropout with a baseline, a failing
    robot beyond N)."""
    n = positions.shape[1]
    if baseline is not None and config.dropout > 0:
        msg = 'dropped messages (dropout) act on the planned controller; fly the baseline with dropout = 0.'
        raise ParamsError(msg)
    if config.failure is not None and config.failure.robot >= n:
        msg = f'the failing robot {config.failure.robot} does not exist: the swarm has robots 0..{n - 1}.'
        raise ParamsError(msg)
    return Faults(
        config.seed,
        pose_noise_m=config.pose_noise_m,
        dropout=config.dropout,
        latency_steps=config.latency_steps,
        lag_s=config.lag_s,
        dt_s=config.dt_s,
        failure=config.failure,
        positions=positions,
        velocity=velocity,
    )


def _step_count(tube: VirtualTube, swarm: SwarmParams, config: SimConfig, positions: FloatArray) -> int:
    """The control periods up to the time limit (by default 4 (L + formation length + 2 r_a) / v_min), once the
    trajectory is known to fit the memory available."""
    extent = float(np.ptp(tube.project(positions).l_m))
    limit = config.time_limit_s or 4.0 * (tube.length_m + extent + 2 * swarm.r_a_m) / swarm.v_min_mps
    steps = math.ceil(limit / config.dt_s)
    check_memory(steps + 1, positions.shape[1], limit)
    return steps


def _description(
    tube: VirtualTube,
    swarm: SwarmParams,
    control: ControlParams,
    plan: Plan | None,
    config: SimConfig,
    n: int,
    meta: dict[str, Any] | None,
) -> dict[str, Any]:
    """The run as its log and result describe it."""
    return dict(
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
        **({} if config.initial_positions_m is None else {'start': 'given positions'}),
    )


def _log_step(
    log: LogWriter,
    t_s: float,
    positions: FloatArray,
    velocity: FloatArray,
    commanded: FloatArray,
    r_a: FloatArray,
    projection: Projection,
    density: float,
) -> None:
    """Append one control period to the log."""
    log.append(
        t_s=np.float64(t_s),
        positions_m=positions,
        velocities_mps=velocity,
        commands_mps=commanded,
        r_a_m=r_a,
        l_m=projection.l_m,
        clearance_m=projection.clearance_m,
        forward_speed_mps=np.einsum('ij,ij->j', velocity, projection.tangent),
        density_per_m2=np.float64(density),
    )


def _result(
    log: LogWriter,
    description: dict[str, Any],
    tube: VirtualTube,
    swarm: SwarmParams,
    plan: Plan | None,
    replanner: Replanner | None,
    working: NDArray[np.bool_],
    dt_s: float,
) -> SimResult:
    """The run's result from its log: the passage's metrics against the plan as flown, also written to the log."""
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
        description['replans'] = [asdict(call) for call in replanner.calls]
    log.flush(metrics=metrics.to_json(), finished=True)
    outside = dynamics_violations(arrays['velocities_mps'], arrays['commands_mps'], swarm, dt_s)
    return SimResult(
        **arrays, metrics=metrics, planned=plan is not None, meta=description, flown=flown, dynamics_violations=outside
    )
