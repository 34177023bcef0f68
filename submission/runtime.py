"""The body of a Robotarium submission: the flight of :mod:`robotarium_exp.flight`, saving what the testbed returns.

:mod:`submission.builder` writes a single file: a header, the scene's data (``DATA``: what
:func:`robotarium_exp.experiment.flight_data` gives, rounded), the sources of the modules in ``INLINED_MODULES``
(the onboard modules of :mod:`vtube_planning.onboard`, the barrier rows, the safety filter and the flight: the code
the bundled experiment runs) and of the functions in ``INLINED_FUNCTIONS`` (the unicycle map), then this module's
code below the marker line. Imported as a module (tests, benchmarks) it takes them from the package instead.

On the testbed it constructs the Robotarium with the scene's initial conditions and flies: every period, the
swarm step on the control points, the safety filter of :mod:`robotarium_exp.safety` (barrier certificate and speed
band in one QP, solved with scipy; the testbed's certificate cannot hold the band), the speed-constrained map and the
near-identity map with uniform wheel scaling, ``set_velocities``, ``step``. Robots that leave the tube park beyond
its exit. It saves every logged array with ``np.save`` every 100 steps and at the end, prints a one-line JSON
summary (it lands in ``log.txt``), and calls the generation's end-of-script function.
"""

from __future__ import annotations

# ---- inlined by the builder: the modules and functions named below replace this import block ----
from robotarium_exp.flight import Period, build_flight, fly
from vtube_planning import onboard

INLINED_MODULES = (
    *onboard.MODULES,
    'robotarium_exp.rps.utilities.barrier_rows',
    'robotarium_exp.safety',
    'robotarium_exp.flight',
)
INLINED_FUNCTIONS = (
    ('unicycle_mapping.errors', ('MappingError', 'as_columns', 'positive')),
    ('unicycle_mapping.mapping', ('si_to_uni', 'si_to_uni_constrained', 'uni_to_si_states')),
    ('unicycle_mapping.wheels', ('wheel_speeds', 'scale_to_wheel_limits')),
)
# ---- runtime ----
import json
import os
import time
from typing import Any

import numpy as np

SAVE_EVERY = 100


def draw_tube(r, data: dict) -> None:
    """Draw the tube on the arena figure (projected onto the testbed), if the Robotarium has a figure."""
    axes = getattr(r, '_axes_handle', None) or getattr(r, 'axes', None)
    if axes is None or isinstance(axes, list):
        return
    edges = np.asarray(data['tube_edges'], dtype=float)  # (2, 2, K): left and right boundary
    for side in edges:
        axes.plot(side[0], side[1], color='tab:blue', linewidth=2, zorder=0)


def save_log(log: dict, prefix: str = 'vtube_') -> None:
    """np.save every logged array (the testbed returns files the script writes)."""
    for name, rows in log.items():
        np.save(prefix + name + '.npy', np.array(rows))


def run(data: dict, robotarium_module: Any, *, max_steps: int | None = None) -> dict:
    """The experiment loop; returns (and prints) the summary."""
    n = int(data['n_robots'])
    show = os.environ.get('VTUBE_HEADLESS', '') != '1'
    r = robotarium_module.Robotarium(
        number_of_robots=n,
        show_figure=show,
        sim_in_real_time=show,
        initial_conditions=np.array(data['initial_conditions'], dtype=float),
    )
    if show:
        draw_tube(r, data)
    dt = float(getattr(r, 'TIME_STEP', getattr(r, 'time_step', data['time_step_s'])))
    flight = build_flight(data)
    log: dict = {name: [] for name in ('t', 'wall', 'poses', 'dxu', 'r_a', 'l', 'density', 'barrier_correction')}
    started = time.time()
    closest = [np.inf]

    def record(step: int, period: Period) -> None:
        poses = period.poses
        gaps = np.hypot(*(poses[:2, :, None] - poses[:2, None, :])) + np.eye(n) * 1e9
        closest[0] = min(closest[0], float(gaps.min()))
        for name, value in (
            ('t', step * dt),
            ('wall', time.time() - started),
            ('poses', poses),
            ('dxu', period.dxu),
            ('r_a', period.step.r_a_m),
            ('l', period.step.projection.l_m),
            ('density', period.step.density_per_m2),
            ('barrier_correction', period.barrier_correction_mps),
        ):
            log[name].append(np.array(value, copy=True))
        if step % SAVE_EVERY == SAVE_EVERY - 1:
            save_log(log)

    completed, steps = fly(r, flight, dt, int(max_steps if max_steps is not None else data['max_steps']), record)
    save_log(log)
    iterations = getattr(r, 'iterations', None) or getattr(r, '_iteration', None) or getattr(r, '_iterations', 0)
    errors = dict(getattr(r, 'errors', None) or getattr(r, '_errors', None) or {})
    summary = {
        'vtube_summary': 1,
        'scene': data['scene'],
        'planned': data['planned'],
        'robots': n,
        'dt_s': dt,
        'steps': steps,
        'completed': completed,
        'iterations': int(iterations or 0),
        'min_center_distance_m': round(closest[0], 4),
        'barrier_correction_max_mps': round(float(np.max(log['barrier_correction'])), 4),
        'band_dropped_steps': flight.safety.stats.band_dropped if flight.safety is not None else 0,
        'filter_failures': flight.safety.stats.failures if flight.safety is not None else 0,
        'errors': {k: v for k, v in errors.items() if isinstance(v, int)},
    }
    print(json.dumps(summary))
    if hasattr(r, 'debug'):
        r.debug()
    else:
        r.call_at_scripts_end()
    return summary
