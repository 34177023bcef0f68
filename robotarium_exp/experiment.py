"""The tube experiment on a Robotarium, written against the ``rps`` API only.

Any ``Robotarium`` class can be passed in (ours, the PyPI simulator, the testbed's): it is constructed with the
keywords both generations accept and used only through ``get_poses``, ``set_velocities`` and ``step``. Each step:

1. poses -> control points p + d e_theta (:mod:`unicycle_mapping`);
2. the swarm controller of :mod:`vtube_planning.swarm.control` on the control points, with the plan (or without:
   constant mid-range speed, constant r_a); robots that have left the tube drive to parking slots beyond the exit;
3. the single-integrator barrier certificate with the arena boundary (optional), its correction logged per robot;
4. the near-identity map to [v; omega] and uniform wheel scaling (curvature kept, no per-wheel clipping left for
   the testbed to do);
5. ``set_velocities`` and ``step``; r_a advances by (a3) when planning.

Every step is logged (``vtube_planning.swarm.log``: rewritten atomically, so an interrupted run leaves a readable
file). The run ends when every robot has parked past the exit, or at the step limit.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.errors import ExperimentError
from robotarium_exp.rps.utilities.barrier_certificates import create_si_barrier_certificate_with_boundary
from unicycle_mapping import scale_to_wheel_limits, si_to_uni, uni_to_si_states
from vtube_planning.swarm.control import avoidance_radius_rate, velocity_command
from vtube_planning.planning.density import swarm_area
from vtube_planning.swarm.metrics import swarm_metrics
from vtube_planning.planning.plan import Plan
from vtube_planning.geometry.scene import Scene
from vtube_planning.swarm.log import LogWriter
from vtube_planning.swarm.simulate import default_constant_speed

FloatArray = NDArray[np.float64]

ARENA = (-1.6, 1.6, -1.0, 1.0)
IC_SPACING_M = 0.4
"""Initial conditions at least this far apart: what the V2 initialization reaches reliably (robotarium.md §2.6)."""
IC_BOX = (1.375, 0.875)
"""|x|, |y| bounds of initial conditions (the box the V2 simulator samples from)."""
WHEEL_RADIUS, BASE_LENGTH, MAX_WHEEL_SPEED = 0.016, 0.11, 12.5


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
    """What a run produced: per-step arrays, the simulator's validation counts, metrics, parking time."""

    arrays: dict[str, FloatArray]
    errors: dict[str, int]
    metrics: dict[str, Any]
    completed: bool
    meta: dict[str, Any] = field(default_factory=dict)


def initial_conditions(scene: Scene) -> FloatArray:
    """Entry formation (3xN): rows across the tube, headings along it, every pair at least IC_SPACING_M apart.

    Rows and columns start IC_SPACING_M apart along and across the tube; on a bend the inner side converges, so the
    spacing grows until every pair keeps IC_SPACING_M.
    """
    tube, n = scene.tube, scene.swarm.n_robots
    lam0 = float(tube.half_width(0.0))
    cols = max(1, int(math.floor(2 * (lam0 - 0.1) / IC_SPACING_M)) + 1)
    l_first = _first_inside_box(scene)
    for spacing in IC_SPACING_M * (1.0 + 0.02 * np.arange(50)):
        poses = []
        for k in range(n):
            row, col = divmod(k, cols)
            in_row = min(cols, n - row * cols)
            l_k = l_first + spacing * (math.ceil(n / cols) - 1 - row)
            y = (col - 0.5 * (in_row - 1)) * IC_SPACING_M
            point = tube.center_at(l_k) + y * tube.normal(l_k)
            tangent = tube.tangent(l_k)
            poses.append([point[0], point[1], math.atan2(tangent[1], tangent[0])])
        ic = np.array(poses).T
        gaps = np.hypot(*(ic[:2, :, None] - ic[:2, None, :]))[np.triu_indices(n, 1)]
        if gaps.size == 0 or gaps.min() >= IC_SPACING_M - 1e-12:
            break
    if np.any(np.abs(ic[0]) > IC_BOX[0]) or np.any(np.abs(ic[1]) > IC_BOX[1]):
        msg = (f'scene {scene.name!r}: the entry formation leaves the box |x| <= {IC_BOX[0]}, |y| <= {IC_BOX[1]} '
               'the testbed initializes robots in; move the tube entrance inwards or use fewer robots.')
        raise ExperimentError(msg)
    return ic


def _first_inside_box(scene: Scene) -> float:
    """Smallest arc length whose whole cross-section (minus 0.1 m) lies inside the initialization box."""
    tube = scene.tube
    for l_m in np.linspace(0.0, tube.length_m, 2001):
        left, right = tube.boundaries(float(l_m))
        if np.all(np.abs(np.vstack([left, right])) <= np.array(IC_BOX)):
            return float(l_m) + 0.02
    msg = f'scene {scene.name!r}: no cross-section of the tube lies inside the initialization box.'
    raise ExperimentError(msg)


def parking_slots(scene: Scene) -> FloatArray:
    """Slots (2xN) beyond the exit, 0.25 m apart (the barrier keeps 0.2 m), filled farthest first."""
    tube, n = scene.tube, scene.swarm.n_robots
    end, tangent = tube.center_at(tube.length_m), tube.tangent(tube.length_m)
    normal = np.array([-tangent[1], tangent[0]])
    rows = max(1, min(n, 5))
    slots = []
    for k in range(n):
        depth, lane = divmod(k, rows)
        slots.append(end + (0.45 - 0.25 * depth) * tangent + (lane - 0.5 * (rows - 1)) * 0.25 * normal)
    return np.array(slots).T


def run_experiment(robotarium_class: Any, scene: Scene, plan: Plan | None, config: ExperimentConfig | None = None,
                   *, log_path: str | Path | None = None, robotarium_kwargs: dict[str, Any] | None = None
                   ) -> ExperimentResult:
    """Fly the scene's swarm through its tube on a Robotarium and park it beyond the exit."""
    config = config or ExperimentConfig()
    if config.planning and plan is None:
        msg = 'planning is on but no plan was given; plan the scene first (vtube plan) or set planning=False.'
        raise ExperimentError(msg)
    tube, swarm, control = scene.tube, scene.swarm, scene.control
    n = swarm.n_robots
    ic = initial_conditions(scene)
    r = robotarium_class(number_of_robots=int(n), show_figure=False, sim_in_real_time=False, initial_conditions=ic,
                         **(robotarium_kwargs or {}))
    d = config.projection_distance_m
    barrier = create_si_barrier_certificate_with_boundary(safety_radius=config.safety_radius_m,
                                                          magnitude_limit=swarm.v_max_mps, boundary_points=ARENA)
    slots = parking_slots(scene)
    slot_of = np.full(n, -1)
    r_a = np.full(n, swarm.r_a_m)
    cap = control.radius_cap(swarm)
    speed = default_constant_speed(swarm)
    meta = {'scene': scene.name, 'planned': config.planning, 'barrier': config.barrier, 'n_robots': n,
            'dt_s': 0.033, 'config': asdict(config), 'swarm': asdict(swarm), 'control': asdict(control),
            'length_m': tube.length_m, 'initial_conditions': ic.tolist()}
    writer = LogWriter(log_path, meta, flush_every=config.log_every) if log_path is not None else None
    rows: dict[str, list[FloatArray]] = {}
    completed = False
    for step in range(config.max_steps):
        poses = r.get_poses()
        points = uni_to_si_states(poses, d)
        projection = tube.project(points)
        l_m = projection.l_m
        in_tube = l_m <= tube.length_m
        density = float(n / swarm_area(tube, l_m.min(), l_m.max(), swarm.r_a_m)[0])
        forward = plan.speed(l_m) if config.planning and plan is not None else np.full(n, speed)
        nominal = velocity_command(points, r_a, forward, tube, swarm, control, projection).velocity
        for k in np.flatnonzero(~in_tube & (slot_of < 0)):
            slot_of[k] = int((slot_of >= 0).sum())
        parked = slot_of >= 0
        to_slot = slots[:, slot_of[parked]] - points[:, parked]
        nominal[:, parked] = to_slot * np.minimum(1.0, swarm.v_max_mps / np.maximum(np.hypot(*to_slot), 1e-9))
        safe = barrier(nominal, points) if config.barrier else nominal
        dxu, _ = scale_to_wheel_limits(si_to_uni(safe, poses, d), BASE_LENGTH, WHEEL_RADIUS, MAX_WHEEL_SPEED)
        row = {'t_s': np.float64(step * 0.033), 'poses': poses, 'points_m': points, 'si_nominal_mps': nominal,
               'si_safe_mps': safe, 'dxu': dxu, 'barrier_correction_mps': np.hypot(*(safe - nominal)),
               'r_a_m': r_a.copy(), 'l_m': l_m, 'clearance_m': projection.clearance_m,
               'density_per_m2': np.float64(density)}
        for key, value in row.items():
            rows.setdefault(key, []).append(np.asarray(value))
        if writer is not None:
            writer.append(**row)
        if parked.all() and np.all(np.hypot(*(slots[:, slot_of] - points)) < 0.03):
            completed = True
            break
        r.set_velocities(np.arange(n), dxu)
        r.step()
        if config.planning and plan is not None:
            r_a = np.minimum(cap, r_a + 0.033 * avoidance_radius_rate(density, plan.density(l_m), control))
    arrays = {key: np.stack(values) for key, values in rows.items()}
    errors = dict(getattr(r, 'errors', None) or getattr(r, '_errors', {}) or {})
    metrics = swarm_metrics(arrays['t_s'], arrays['poses'][:, :2], arrays['l_m'], arrays['clearance_m'],
                            tube.length_m, swarm)
    metrics['barrier_correction_mean_mps'] = float(arrays['barrier_correction_mps'].mean())
    metrics['barrier_correction_max_mps'] = float(arrays['barrier_correction_mps'].max())
    metrics['barrier_failures'] = barrier.stats.failures if config.barrier else 0
    metrics['duration_s'] = float(getattr(r, 'iterations', step + 1) * 0.033)
    if writer is not None:
        writer.flush(metrics=metrics, errors=errors, completed=completed, finished=True)
    return ExperimentResult(arrays=arrays, errors=errors, metrics=metrics, completed=completed, meta=meta)
