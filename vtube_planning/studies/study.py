"""One run of a study (`Point`, `run_point`) and the modes a study compares.

The paper's comparison flies every scene and seed once with the plan (planned speed, r_a following (a3)) and once
without (constant mid-range speed, constant r_a), from the same jittered initial formation; on scenes C and D the
paper's baselines (optimized flocking with v_min = 0 as the paper ran it and a speed-constrained variant;
distributed NMPC) too. The ablation modes (ABLATIONS) each switch one part of the method off on the same code path.
Reports are in `vtube_planning.studies.paper_report` and `vtube_planning.studies.study_report`; every study runs as a campaign
(`vtube_planning.studies.campaign`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, replace
from typing import Any, Literal

import numpy as np

from vtube_planning.baselines.flocking import FlockingParams, flocking_command
from vtube_planning.baselines.nmpc import NmpcParams, NmpcSwarm
from vtube_planning.errors import ParamsError
from vtube_planning.geometry.bends import too_tight
from vtube_planning.geometry.from_maps.maps import CLUTTER, WIDTH_M, scene_on_map
from vtube_planning.geometry.scene import Scene, load_scene, scene_data, scene_from_data
from vtube_planning.onboard import Saturation
from vtube_planning.params import ControlParams, PlanningOptions, SwarmParams
from vtube_planning.planning.plan import Plan
from vtube_planning.planning.planner import plan_convex
from vtube_planning.swarm.faults import FailureMode, RobotFailure
from vtube_planning.swarm.foresight import with_foresight
from vtube_planning.swarm.metrics import tracking_errors
from vtube_planning.swarm.period import Baseline
from vtube_planning.swarm.simulate import SimConfig, SimResult, default_constant_speed, simulate

MODES = ('planning', 'no planning')
BASELINE_MODES = ('flocking', 'flocking (v_min)', 'nmpc')
COMPENSATIONS = ('none', 'known', 'known-1', 'known+1')
"""What delay the controller compensates (`Point.compensated`)."""
BASELINE_SCENES = ('C', 'D')


def _baseline_setup(mode: str, scene: Scene, swarm: SwarmParams, dt_s: float) -> Setup:
    """A baseline's swarm law as the simulator's ``baseline`` hook (positions, velocities, projection), and for
    NMPC its solver, whose convergence the grid reports."""
    if mode == 'nmpc':
        nmpc = NmpcSwarm(scene.tube, NmpcParams.for_swarm(swarm))
        law = lambda positions, velocities, projection: nmpc.command(positions, velocities, projection, dt_s)
        return Setup(None, scene.control, None, law, nmpc)
    params = FlockingParams.scaled(swarm, speed_constrained=mode == 'flocking (v_min)')
    law = lambda positions, velocities, projection: flocking_command(positions, velocities, projection, params)
    return Setup(None, scene.control, None, law)


# ---------------------------------------------------------------------- the ablation grid


@dataclass(frozen=True)
class Ablation:
    """Which parts of the method a mode keeps, all flown by the same simulator and swarm step.

    ``plan``: the plan flown, ``'full'``, ``'without (p7)'`` (planned with ``predictive_model = 'none'``), ``'flat'``
    (the full plan's grid with the constant speed and density rho_d: (a3) then tracks a flat rho_d) or ``'none'``
    (constant speed, constant r_a); ``a3``: whether r_a follows (a3) (off: its gain and feed-forward are zero);
    ``speed``: the constant forward speed of ``'flat'`` and ``'none'``, ``'mid'`` = (v_min + v_max) / 2 or
    ``'v_max'``; ``replan_every_s``: replan the rest of the tube from the measured state this often while flying
    (0: never; [`SimConfig`][vtube_planning.swarm.simulate.SimConfig]); ``freedom``: what the plan is held to, the
    planning option of `vtube_planning.params.FREEDOMS`.
    """

    plan: Literal['full', 'without (p7)', 'flat', 'none']
    a3: bool
    speed: Literal['mid', 'v_max'] = 'mid'
    replan_every_s: float = 0.0
    freedom: Literal['paper', 'relaxed'] = 'paper'


ABLATIONS = {
    'planning': Ablation('full', a3=True),
    'planning without (p7)': Ablation('without (p7)', a3=True),
    'planned speed, (a3) off': Ablation('full', a3=False),
    'constant speed, (a3) to rho_d': Ablation('flat', a3=True),
    'no planning': Ablation('none', a3=False),
    'no planning at v_max': Ablation('none', a3=False, speed='v_max'),
}
REPLANNING_MODES = {'replanning every 0.5 s': Ablation('full', a3=True, replan_every_s=0.5)}
"""Modes that replan online (not part of ``vtube ablation``'s grid; campaigns name them)."""
FREEDOM_MODES = {'planning (relaxed)': Ablation('full', a3=True, freedom='relaxed')}
"""The plan with the unplanned swarm's freedom in the paper's model: from v_max, (p3) and (p4) left out (not part
of ``vtube ablation``'s grid; campaigns name it)."""
MODELS = {'paper': False, 'acceleration limits': True}
"""Robot models: the paper's p' = sat(v_c), or every robot also held to the acceleration limits (3), (4)."""
CONTROLLERS = ('law', 'foresight')
"""What commands every mode's robots: the law (or the baseline's) alone, or under the foresight
(`vtube_planning.swarm.foresight`), the same for every mode of a cell."""
GRID_SCENES = ('C', 'D')
"""The scenes whose plans pre-expand (p7 binds before the narrowing); on A and B the plan is the same without it."""


def check_turns(scene: Scene, models: Iterable[str]) -> None:
    """[`ParamsError`][vtube_planning.errors.ParamsError] when one of the robot ``models`` holds robots to (2)-(4)
    and the scene's tube has a bend none of them can turn through (`vtube_planning.geometry.bends.too_tight`)."""
    turn = scene.swarm.v_min_mps**2 / scene.swarm.a_n_mps2
    why = too_tight(scene.tube, turn, scene.swarm.r_p_m) if any(MODELS.get(m) for m in models) else None
    if why is not None:
        raise ParamsError(f'scene {scene.name!r} under the acceleration limits: {why}.')


def physics_text(modes: Iterable[str]) -> str:
    """What the ``modes`` fly, beside the robot model and controller their setting names: the freedom of each
    mode's plan, or its constant speed, or its baseline's law."""
    parts = []
    for mode in modes:
        ablation = (ABLATIONS | REPLANNING_MODES | FREEDOM_MODES).get(mode)
        if ablation is None:
            parts.append(f"{mode}: the baseline's own law")
        elif ablation.plan in ('none', 'flat'):
            speed = 'v_max' if ablation.speed == 'v_max' else '(v_min + v_max) / 2'
            parts.append(f'{mode}: {speed} from the first period')
        elif ablation.freedom == 'relaxed':
            parts.append(f'{mode}: a plan from v_max, (p3) and (p4) left out')
        else:
            parts.append(f"{mode}: the paper's plan, (p3) from v_min and (p4)")
    return (
        'Physics: every mode flies the robot model of its setting (paper: (2) only; acceleration limits: (2)-(4) '
        'for every robot) under the controller it names (the law where none is named); ' + '; '.join(parts) + '.'
    )


@dataclass(frozen=True)
class Setup:
    """What one mode hands the simulator: the plan (or None), the control parameters, the constant speed."""

    plan: Plan | None
    control: ControlParams
    constant_speed_mps: float | None
    baseline: Baseline | None = None
    nmpc: NmpcSwarm | None = None
    replan_every_s: float = 0.0


def ablation_setup(mode: str, scene: Scene, swarm: SwarmParams, dt_s: float) -> Setup:
    """The simulator's inputs for ``mode`` (a key of ABLATIONS, or of BASELINE_MODES)."""
    if mode in BASELINE_MODES:
        return _baseline_setup(mode, scene, swarm, dt_s)
    ablation = (ABLATIONS | REPLANNING_MODES | FREEDOM_MODES)[mode]
    speed = default_constant_speed(swarm) if ablation.speed == 'mid' else swarm.v_max_mps
    control = scene.control if ablation.a3 else replace(scene.control, k_ra_m3ps=0.0, feedforward=False)
    if ablation.plan == 'none':
        return Setup(None, control, speed)
    model = 'none' if ablation.plan == 'without (p7)' else scene.planning.predictive_model
    plan = _cached_plan(scene, swarm, model, ablation.freedom)
    if ablation.plan == 'flat':
        plan = replace(
            plan,
            speed_mps=np.full_like(plan.speed_mps, speed),
            density_per_m2=np.full_like(plan.density_per_m2, swarm.rho_d_per_m2),
            solved=replace(plan.solved, method='flat'),
        )
    return Setup(plan, control, None, replan_every_s=ablation.replan_every_s)


_PLANS: dict[tuple[str, SwarmParams, PlanningOptions], Plan] = {}
"""The plans of this process (each worker of a study has its own), planned once per scene file, swarm and options."""


def _cached_plan(scene: Scene, swarm: SwarmParams, model: str, freedom: str = 'paper') -> Plan:
    """The scene's plan for this swarm with (p7) read as ``model``, held to ``freedom``."""
    options = replace(scene.planning, predictive_model=model, freedom=freedom)
    key = (scene.source, swarm, options)
    if key not in _PLANS:
        _PLANS[key] = plan_convex(scene.tube, swarm, options, scene=scene.name)
    return _PLANS[key]


@dataclass(frozen=True)
class Point:
    """One run of a study: where (scene, swarm size N, and a random map whose generated tube replaces the scene's:
    ``map`` a family of `vtube_planning.geometry.from_maps.maps` or 'none', with its seed and difficulty), how (mode of
    ABLATIONS or BASELINE_MODES, robot model of MODELS, saturation of SATURATIONS), which seed, and which faults
    ([`SimConfig`][vtube_planning.swarm.simulate.SimConfig]; ``failure``: 'none', or the failing robot's mode, 'stop' or
    'coast', placed by `RunSettings`). ``n_robots`` and ``saturation`` None: the scene's own; ``narrowest_m``: the
    tube's narrowest half-width (`narrowed`), 0: the scene's own."""

    scene: str
    map: str = 'none'
    map_seed: int = 0
    map_clutter: int = CLUTTER
    map_width_m: float = WIDTH_M
    mode: str = 'planning'
    n_robots: int | None = None
    seed: int = 0
    model: str = 'paper'
    saturation: Saturation | None = None
    pose_noise_m: float = 0.0
    latency_steps: int = 0
    lag_s: float = 0.0
    compensation: str = 'none'
    failure: FailureMode | Literal['none'] = 'none'
    dropout: float = 0.0
    controller: str = 'law'
    narrowest_m: float = 0.0

    def compensated(self) -> tuple[float, float]:
        """The delay (periods) and lag (s) the controller compensates: none, or the run's own (``'known'``), or
        the run's delay misjudged by whole periods (``'known-1'``, ``'known+1'``: one period less or more; never
        below 0)."""
        if self.compensation == 'none':
            return 0.0, 0.0
        offset = {'known': 0, 'known-1': -1, 'known+1': 1}[self.compensation]
        return float(max(0, self.latency_steps + offset)), self.lag_s

    def load_scene(self) -> Scene:
        """The scene flown: the named one, narrowed to ``narrowest_m``, on its random map if the point has one."""
        scene = narrowed(load_scene(self.scene), self.narrowest_m)
        if self.map == 'none':
            return scene
        return scene_on_map(scene, self.map, self.map_seed, clutter=self.map_clutter, width_m=self.map_width_m)


def narrowed(scene: Scene, narrowest_m: float) -> Scene:
    """``scene`` with its tube's narrowest half-width set to ``narrowest_m`` (0: the scene as it is): every part of
    the width profile that ends at the narrowest half-width ends at ``narrowest_m`` instead, the rest of the file
    unchanged (C, D: the narrowing ends there and the tube keeps that width). A tube that does not narrow from its
    start, or ``narrowest_m`` not below the start, raises [`ParamsError`][vtube_planning.errors.ParamsError]."""
    if narrowest_m == 0.0:
        return scene
    data = scene_data(scene.text, scene.source)
    width = data['tube']['width']
    ends = [part['to_m'] for part in width['parts'] if 'to_m' in part]
    if not ends or min(ends) >= width['start_m'] or not 0.0 < narrowest_m < width['start_m']:
        msg = (
            f'scene {scene.name!r}: narrowest_m = {narrowest_m:g} needs a tube that narrows from its start '
            f'half-width ({width["start_m"]:g} m) and a value in (0, {width["start_m"]:g}) m; give such a value, '
            "or 0 for the scene's own."
        )
        raise ParamsError(msg)
    for part in [part for part in width['parts'] if part.get('to_m') == min(ends)]:
        part['to_m'] = narrowest_m
    narrow = scene_from_data(data, name=scene.name, source=f'{scene.source}, narrowest {narrowest_m:g} m')
    return replace(narrow, text=scene.text)


@dataclass(frozen=True)
class RunSettings:
    """What every run of a study shares: the simulator's step and initial jitter, and where the failing robot fails
    (robot index ``failure_robot``, at ``failure_at`` times the tube's length)."""

    dt_s: float = 0.02
    jitter_m: float = 0.05
    failure_robot: int = 0
    failure_at: float = 0.5


def run_point(point: Point, settings: RunSettings = RunSettings()) -> dict[str, Any]:
    """Fly one run and measure it: the passage's metrics, the density error against the *full* plan's rho* (the
    same reference for every mode: mean |rho - rho*(l_c)| while the swarm's centre is in the tube), the share of
    in-tube robot-steps moving backwards, and NMPC's converged share (NaN for the other modes)."""
    scene = point.load_scene()
    check_turns(scene, (point.model,))
    if point.compensation != 'none' and point.mode in BASELINE_MODES:
        msg = f'delay compensation acts in the swarm step, which the baseline {point.mode!r} does not fly; use none.'
        raise ParamsError(msg)
    delay, lag = point.compensated()
    control = replace(
        scene.control,
        saturation=point.saturation or scene.control.saturation,
        compensate_delay_steps=delay,
        compensate_lag_s=lag,
    )
    control = with_foresight(control, scene.swarm) if point.controller == 'foresight' else control
    scene = replace(scene, control=control)
    swarm = replace(scene.swarm, n_robots=point.n_robots or scene.swarm.n_robots)
    reference = _cached_plan(scene, swarm, scene.planning.predictive_model)  # the full plan
    setup = ablation_setup(point.mode, scene, swarm, settings.dt_s)
    failure = None
    if point.failure != 'none':
        failure = RobotFailure(settings.failure_robot, settings.failure_at * scene.tube.length_m, point.failure)
    config = SimConfig(
        dt_s=settings.dt_s,
        jitter_m=settings.jitter_m,
        seed=point.seed,
        acceleration_limits=MODELS[point.model],
        pose_noise_m=point.pose_noise_m,
        latency_steps=point.latency_steps,
        lag_s=point.lag_s,
        failure=failure,
        dropout=point.dropout,
        replan_every_s=setup.replan_every_s,
    )
    result = simulate(
        scene.tube,
        swarm,
        setup.control,
        plan=setup.plan,
        config=config,
        constant_speed_mps=setup.constant_speed_mps,
        baseline=setup.baseline,
    )
    row = _grid_metrics(result, reference, scene.tube.length_m)
    row['nmpc_converged_share'] = setup.nmpc.converged_share if setup.nmpc is not None else math.nan
    return row


def _grid_metrics(result: SimResult, reference: Plan, length_m: float) -> dict[str, Any]:
    """A run's row: the passage's metrics, the density error against ``reference``, the reversing share."""
    m = result.metrics
    tracking = tracking_errors(result.l_m, result.forward_speed_mps, result.density_per_m2, reference, length_m)
    in_tube = (result.l_m >= 0.0) & (result.l_m <= length_m)
    backwards = (result.forward_speed_mps < 0.0) & in_tube
    return {
        'passing_time_s': m.passing_time_s,
        'min_distance_m': m.min_distance_m,
        'collision_pairs': m.collision_pairs,
        'incursion_depth_m': max(0.0, m.collision_distance_m - m.min_distance_m),
        'tube_violation_steps': m.tube_violation_steps,
        'completed': m.completed,
        'passed_share': m.robots_passed / m.robots_counted,
        'density_error_per_m2': tracking.get('density_tracking_mean_per_m2', math.nan),
        'reversing_share': float(backwards.sum() / max(1, in_tube.sum())),
    }
