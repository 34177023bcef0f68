"""The body of a Robotarium submission: the flight of `robotarium_exp.flight`, saving what the testbed returns.

`submission.builder` writes a single file: a header, the flight's data (``DATA``: the plain form of
`FlightData`), the sources of the modules in ``INLINED_MODULES`` (the
onboard modules of [`vtube_planning.onboard`][vtube_planning.onboard], the barrier rows, the safety filter, the flight
data and the flight: the code the bundled experiment runs), the functions in ``INLINED_FUNCTIONS`` (the unicycle map)
and the constants in ``INLINED_CONSTANTS`` (the log schema's format and version), then this module's code below the
marker line. Imported as a module (tests, benchmarks) it takes them from the package instead.

On the testbed it constructs the Robotarium with the flight's initial conditions and flies it (`fly`). It
writes the trajectory log of `vtube_planning.log` as files the testbed returns: one ``vtube_NAME.npy``
per logged array (``t_s``, ``positions_m``, ``headings_rad``, ...) every 100 steps and at the end, and the
description in ``vtube_meta.json`` (format, version, scene, tube fingerprint, the flight's start after the
initialization: `flight_start`; at the end ``finished`` with the simulator's counts).
The first row of the arrays is the flight's first period, so ``vtube analyze`` of the returned files times the
passage as ``vtube robotarium run`` does. It prints a one-line JSON summary (it lands in ``log.txt``) and calls the generation's
end-of-script function.
"""

from __future__ import annotations

# ---- inlined by the builder: the modules, functions and constants named below replace this import block ----
from robotarium_exp.flight import Period, RobotariumLike, build_flight, flight_start, fly, robotarium_steps
from robotarium_exp.flight_data import FlightData
from robotarium_exp.safety import SafetyFilter
from vtube_planning import onboard
from vtube_planning.log import LOG_FORMAT, LOG_VERSION

INLINED_MODULES = (
    *onboard.MODULES,
    'robotarium_exp.rps.utilities.barrier_rows',
    'robotarium_exp.safety',
    'robotarium_exp.flight_data',
    'robotarium_exp.flight',
)
INLINED_FUNCTIONS = (
    ('unicycle_mapping.errors', ('MappingError', 'as_columns', 'positive')),
    ('unicycle_mapping.mapping', ('si_to_uni', 'si_to_uni_constrained', 'uni_to_si_states')),
    ('unicycle_mapping.wheels', ('wheel_speeds', 'scale_to_wheel_limits')),
)
INLINED_CONSTANTS = (
    ('vtube_planning.log', ('LOG_FORMAT', 'LOG_VERSION')),
    ('unicycle_mapping.wheels', ('WHEEL_LIMIT_SHARE',)),
)
# ---- runtime ----
import json
import os
import time
from collections.abc import Callable
from typing import Protocol

import numpy as np

SAVE_EVERY = 100
FILE_PREFIX = 'vtube_'
META_FILE = 'vtube_meta.json'


class RobotariumModule(Protocol):
    """What the file uses of ``rps.robotarium``."""

    Robotarium: Callable[..., RobotariumLike]


def draw_tube(r: object, data: FlightData) -> None:
    """Draw the tube's boundaries and the virtual obstacles (filled grey outlines: V2's ``obstacles=`` would draw
    line segments only, and the classic API has none) on the arena figure, if the Robotarium has a figure."""
    axes = getattr(r, '_axes_handle', None) or getattr(r, 'axes', None)
    if axes is None or isinstance(axes, list):
        return
    for side in data.tube_edges_m:
        axes.plot(side[0], side[1], color='tab:blue', linewidth=2, zorder=0)
    for outline in data.obstacle_outlines_m:
        axes.fill(outline[0], outline[1], color='0.55', alpha=0.8, linewidth=0, zorder=0)


def save_log(rows: dict[str, list[np.ndarray]], meta: dict[str, object]) -> None:
    """np.save every logged array, then the log's description (the testbed returns the files a script writes)."""
    for name, values in rows.items():
        np.save(FILE_PREFIX + name + '.npy', np.array(values))
    with open(META_FILE, 'w', encoding='utf-8') as stream:
        json.dump(meta, stream)


def run(data: FlightData, robotarium_module: RobotariumModule, *, max_steps: int | None = None) -> dict[str, object]:
    """The experiment loop; returns (and prints) the summary."""
    n = data.n_robots
    show = os.environ.get('VTUBE_HEADLESS', '') != '1'
    r = robotarium_module.Robotarium(
        number_of_robots=n,
        show_figure=show,
        sim_in_real_time=show,
        initial_conditions=np.array(data.initial_conditions),
    )
    if show:
        draw_tube(r, data)
    dt = float(getattr(r, 'TIME_STEP', getattr(r, 'time_step', data.time_step_s)))
    flight = build_flight(data)
    meta: dict[str, object] = {
        'format': LOG_FORMAT,
        'version': LOG_VERSION,
        'kind': 'robotarium submission',
        'scene': data.scene,
        'tube_hash': data.tube_hash,
        'planned': data.planned,
        'n_robots': n,
        'dt_s': dt,
        'flight_start': flight_start(r, dt),
    }
    rows: dict[str, list[np.ndarray]] = {}
    started = time.time()

    def record(step: int, period: Period) -> None:
        for name, value in (
            ('t_s', step * dt),
            ('wall_s', time.time() - started),
            ('positions_m', period.poses[:2]),
            ('headings_rad', period.poses[2]),
            ('dxu', period.dxu),
            ('r_a_m', period.step.r_a_m),
            ('points_l_m', period.step.projection.l_m),
            ('density_per_m2', period.step.density_per_m2),
            ('barrier_correction_mps', period.barrier_correction_mps),
            ('flying', period.flying),
            ('band_held', period.band_held),
        ):
            rows.setdefault(name, []).append(np.array(value, copy=True))
        if step % SAVE_EVERY == SAVE_EVERY - 1:
            save_log(rows, meta)

    completed, steps = fly(r, flight, dt, data.max_steps if max_steps is None else max_steps, record)
    summary = _summary(r, data, rows, flight.safety, completed, steps, dt)
    save_log(rows, {**meta, 'finished': True, **summary})
    print(json.dumps({'vtube_summary': 1, **summary}))
    end_of_script = getattr(r, 'debug', None) or getattr(r, 'call_at_scripts_end')  # noqa: B009 - V2, classic
    end_of_script()
    return summary


def _summary(
    r: object,
    data: FlightData,
    rows: dict[str, list[np.ndarray]],
    safety: SafetyFilter | None,
    completed: bool,
    steps: int,
    dt: float,
) -> dict[str, object]:
    """What the file reports of its run (informative: the preflight recounts from the simulator)."""
    positions = np.array(rows['positions_m'])
    i, j = np.triu_indices(data.n_robots, k=1)
    gaps = np.hypot(positions[:, 0, i] - positions[:, 0, j], positions[:, 1, i] - positions[:, 1, j])
    errors = dict(getattr(r, 'errors', None) or getattr(r, '_errors', None) or {})
    return {
        'scene': data.scene,
        'planned': data.planned,
        'robots': data.n_robots,
        'dt_s': dt,
        'steps': steps,
        'completed': completed,
        'iterations': robotarium_steps(r),
        'min_center_distance_m': round(float(gaps.min()), 4) if gaps.size else None,
        'barrier_correction_max_mps': round(float(np.max(rows['barrier_correction_mps'])), 4),
        'band_dropped_steps': safety.stats.band_dropped if safety is not None else 0,
        'filter_failures': safety.stats.failures if safety is not None else 0,
        'errors': {k: v for k, v in errors.items() if isinstance(v, int)},
    }
