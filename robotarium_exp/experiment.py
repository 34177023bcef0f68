"""The tube experiment on a Robotarium, written against the ``rps`` API only.

Any ``Robotarium`` class can be passed in (ours, the PyPI simulator, the testbed's): it is constructed with the
keywords both generations accept and used only through ``get_poses``, ``set_velocities`` and ``step``.

The experiment is the submission without the file: `flight_data` turns a scene, a plan and the options into
the `FlightData` a submission embeds (the tube sampled every centimetre, the
plan's slowness and density, the step's parameters, initial conditions, parking slots, barrier and wheel limits),
and both this module and the submitted file fly it with `robotarium_exp.flight.build_flight` and
`robotarium_exp.flight.fly`. Every period is logged (`vtube_planning.log`: rewritten atomically, so an interrupted run
leaves a readable file). The run ends when every robot has parked past the exit, or at the step limit.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.design import start_formation
from robotarium_exp.errors import ExperimentError
from robotarium_exp.flight import Period, RobotariumLike, build_flight, flight_start, fly
from robotarium_exp.flight_data import FlightData, SafetyData, TubeSamples, Wheels
from robotarium_exp.parking_slots import parking
from robotarium_exp.spec import ROBOTARIUM
from robotarium_exp.tracking import FilterSummary, filter_summary
from robotarium_exp.verifier import VerifierCounts, restart_shared_counters
from vtube_planning.geometry.scene import Scene
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.log import LogWriter
from vtube_planning.planning.plan import Plan
from vtube_planning.swarm.metrics import PassageMetrics, passage_metrics
from vtube_planning.swarm.simulate import default_constant_speed

FloatArray = NDArray[np.float64]

BARRIER_GAIN = 100.0
"""gamma of the barrier rows: the Robotarium certificates' default."""
TUBE_SAMPLE_SPACING_M = 0.01
"""The submission's tube is sampled this finely: arc lengths within 0.1 mm of the exact tube's."""
TUBE_EDGE_POINTS = 120
"""Points of each tube boundary the submission draws on the arena figure."""


@dataclass(frozen=True)
class ExperimentConfig:
    """Options of the tube experiment.

    Parameters
    ----------
    planning
        Track the plan (speed and density); without it, constant mid-range speed and constant r_a.
    barrier
        Filter the commands through the single-integrator barrier certificate with the arena boundary.
    projection_distance_m
        d of the near-identity map: the swarm law acts on the points d ahead of the wheel axles.
    safety_radius_m
        Barrier distance between control points: the testbed's collision test (0.135 m between centres shifted
        0.025 m forward) plus the 2 x 0.025 m between those and the control points, plus margin.
    max_steps
        Stop after this many steps (33 ms each).
    log_every
        Steps between rewrites of the log.
    """

    planning: bool = True
    barrier: bool = True
    projection_distance_m: float = 0.05
    safety_radius_m: float = 0.2
    max_steps: int = 4000
    log_every: int = 50


@dataclass(frozen=True)
class ExperimentResult:
    """What a run produced.

    Attributes
    ----------
    arrays
        The logged rows (the trajectory log's arrays).
    errors
        The simulator's verifier counts.
    metrics
        The passage's measures, on the robots' centres; collisions closer than 2 r_p.
    barrier
        What the safety filter did.
    duration_s
        Simulated time, initialization included: what the testbed counts.
    completed
        Every robot parked.
    planned
        The flight tracked a plan.
    """

    arrays: dict[str, FloatArray]
    errors: VerifierCounts
    metrics: PassageMetrics
    barrier: FilterSummary
    duration_s: float
    completed: bool
    planned: bool


def initial_conditions(scene: Scene) -> FloatArray:
    """The start formation (3xN) of `robotarium_exp.design.start_formation`; refused when it cannot be built."""
    formation = start_formation(scene.tube, scene.swarm.n_robots)
    if formation.problem is not None:
        msg = f'scene {scene.name!r}: {formation.problem}; move the tube entrance inwards or widen it.'
        raise ExperimentError(msg)
    return formation.poses


def flight_data(scene: Scene, plan: Plan | None, config: ExperimentConfig) -> FlightData:
    """Everything the flight needs, rounded to six significant digits: what a submission embeds, so that the
    bundled experiment flies exactly the numbers the testbed will. Without planning the data carry no plan."""
    if config.planning and plan is None:
        msg = 'planning is on but no plan was given; plan the scene first (vtube plan) or set planning=False.'
        raise ExperimentError(msg)
    if plan is not None:
        plan.check_matches(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    tube, swarm = scene.tube, scene.swarm
    samples = tube.sampled(TUBE_SAMPLE_SPACING_M)
    left, right = tube.boundaries(np.linspace(0.0, tube.length_m, TUBE_EDGE_POINTS))
    safety = SafetyData(config.safety_radius_m, BARRIER_GAIN, ROBOTARIUM.arena_m)
    return FlightData(
        scene=scene.name,
        tube_hash=tube.fingerprint(),
        n_robots=swarm.n_robots,
        time_step_s=ROBOTARIUM.time_step_s,
        max_steps=config.max_steps,
        step=scene.control.step_params(swarm),
        constant_speed_mps=default_constant_speed(swarm),
        plan=plan.profile if plan is not None and config.planning else None,
        tube=TubeSamples(samples.l_m, samples.xy_m, samples.half_width_m, samples.area_m2),
        tube_edges_m=np.stack([left.T, right.T]),
        obstacle_outlines_m=scene.obstacles.outlines(),
        initial_conditions=initial_conditions(scene),
        parking_slots=parking(scene.tube, swarm.n_robots),
        projection_distance_m=config.projection_distance_m,
        safety=safety if config.barrier else None,
        wheels=Wheels(ROBOTARIUM.base_length_m, ROBOTARIUM.wheel_radius_m, ROBOTARIUM.max_wheel_speed_radps),
    ).rounded()


def run_experiment(
    robotarium_class: Callable[..., RobotariumLike],
    scene: Scene,
    plan: Plan | None,
    config: ExperimentConfig | None = None,
    *,
    log_path: str | Path | None = None,
    robotarium_kwargs: Mapping[str, object] | None = None,
    log_meta: Mapping[str, object] | None = None,
) -> ExperimentResult:
    """Fly the scene's swarm through its tube on a Robotarium and park it beyond the exit; ``log_meta`` is added
    to the log's description (provenance)."""
    config = config or ExperimentConfig()
    data = flight_data(scene, plan, config)
    tube, swarm = scene.tube, scene.swarm
    dt = ROBOTARIUM.time_step_s
    r = robotarium_class(
        number_of_robots=int(data.n_robots),
        show_figure=False,
        sim_in_real_time=False,
        initial_conditions=np.array(data.initial_conditions),
        **(robotarium_kwargs or {}),
    )
    restart_shared_counters(r)
    flight = build_flight(data)
    description = {**_log_description(scene, config, data, log_meta), 'flight_start': flight_start(r, dt)}
    log = LogWriter(log_path, description, flush_every=config.log_every)
    completed, periods = fly(r, flight, dt, config.max_steps, _recorder(log, tube, dt))
    arrays = log.arrays()
    errors = VerifierCounts.from_simulator(getattr(r, 'errors', None) or getattr(r, '_errors', None) or {})
    metrics = passage_metrics(
        arrays['t_s'],
        arrays['positions_m'],
        arrays['l_m'],
        arrays['clearance_m'],
        tube.length_m,
        collision_distance_m=2.0 * swarm.r_p_m,
        body_radius_m=0.5 * ROBOTARIUM.robot_diameter_m,
    )
    failures = flight.safety.stats.failures if flight.safety is not None else 0
    barrier = filter_summary(arrays, swarm.v_min_mps, swarm.v_max_mps, tube.length_m, dt, failures)
    duration = float(getattr(r, 'iterations', periods) * dt)
    log.flush(
        metrics=metrics.to_json(),
        barrier=asdict(barrier),
        duration_s=duration,
        errors=errors.to_json(),
        completed=completed,
        finished=True,
    )
    return ExperimentResult(arrays, errors, metrics, barrier, duration, completed, data.planned)


def _log_description(
    scene: Scene, config: ExperimentConfig, data: FlightData, extra: Mapping[str, object] | None
) -> dict[str, object]:
    """The log's description of the run (JSON)."""
    return {
        **(extra or {}),
        'kind': 'robotarium experiment',
        'scene': scene.name,
        'tube_hash': data.tube_hash,
        'planned': config.planning,
        'barrier': config.barrier,
        'n_robots': data.n_robots,
        'dt_s': ROBOTARIUM.time_step_s,
        'config': asdict(config),
        'swarm': asdict(scene.swarm),
        'control': asdict(scene.control),
        'length_m': scene.tube.length_m,
        'initial_conditions': data.initial_conditions.tolist(),
    }


def _recorder(log: LogWriter, tube: VirtualTube, dt: float) -> Callable[[int, Period], None]:
    """What the experiment logs of each period: the period's arrays, and the robots' centres on the exact tube."""

    def record(step: int, period: Period) -> None:
        robots = tube.project(period.poses[:2])  # the robots' centres on the exact tube, as the analysis measures
        log.append(
            t_s=np.float64(step * dt),
            positions_m=period.poses[:2],
            headings_rad=period.poses[2],
            points_m=period.points_m,
            si_nominal_mps=period.step.velocity,
            si_safe_mps=period.safe_mps,
            dxu=period.dxu,
            barrier_correction_mps=period.barrier_correction_mps,
            r_a_m=period.step.r_a_m,
            l_m=robots.l_m,
            clearance_m=robots.clearance_m,
            density_per_m2=np.float64(period.step.density_per_m2),
            flying=period.flying,
            band_held=np.array(period.band_held),
        )

    return record
