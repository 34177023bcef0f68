"""How long V2's initializer takes to bring robots to given initial conditions: its distribution over seeds.

The bundled simulator runs V2's initializer with V2's draws (`robotarium_exp.rps_alias.seed_rps`) and, by
default, the testbed's barrier QP solver, so each seed's run is V2's, step for step (``docs/robotarium.md`` §2.6). Used by
``vtube submission check`` to derive the duration to declare, and by ``benchmarks/initializer_durations.py``.
"""

from __future__ import annotations

import contextlib
import io
import os
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from functools import partial

import numpy as np
from numpy.typing import NDArray

import robotarium_exp.rps.robotarium as simulator
from robotarium_exp.rps.errors import RobotariumError
from robotarium_exp.rps_alias import seed_rps
from vtube_planning.studies.executors import map_unordered

INITIALIZATION_LIMIT = 15_000
"""Steps after which an initialization counts as stuck."""


@dataclass(frozen=True)
class InitializerSample:
    """Durations (s, simulated) of the seeds that finished, and the seeds that did not within the step limit."""

    durations_s: tuple[float, ...]
    stuck_seeds: tuple[int, ...]

    @property
    def runs(self) -> int:
        return len(self.durations_s) + len(self.stuck_seeds)


def initializer_durations(
    ic: NDArray[np.float64],
    seeds: Iterable[int],
    limit: int = INITIALIZATION_LIMIT,
    *,
    workers: int | None = None,
    seed_done: Callable[[], None] | None = None,
    ran: Callable[[int, float | None], None] | None = None,
) -> InitializerSample:
    """Run V2's initializer for ``ic`` (3xN) once per seed; a run over ``limit`` steps counts as stuck.

    The seeds are shared among ``workers`` processes (default: one per core); the result does not depend on how
    many. ``seed_done`` is called as each seed's run ends (a progress bar), ``ran`` with the seed and its duration
    (None: stuck), so that what ran is kept however the rest ends.
    """
    seeds = list(seeds)
    workers = max(1, min(workers or os.cpu_count() or 1, len(seeds)))
    done_one = seed_done or (lambda: None)
    results: list[float | None] = [None] * len(seeds)
    for k, duration in map_unordered(partial(_one_seed, ic, limit=limit), seeds, workers=workers):
        results[k] = duration
        if ran is not None:
            ran(seeds[k], duration)
        done_one()
    done = tuple(duration for duration in results if duration is not None)
    stuck = tuple(seed for seed, duration in zip(seeds, results) if duration is None)
    return InitializerSample(done, stuck)


def _one_seed(ic: NDArray[np.float64], seed: int, *, limit: int) -> float | None:
    """One initialization's duration (s), or None when it does not finish within ``limit`` steps."""
    saved = simulator.INITIALIZATION_STEP_LIMIT
    simulator.INITIALIZATION_STEP_LIMIT = limit
    try:
        seed_rps(seed)
        with contextlib.redirect_stdout(io.StringIO()):  # V2's "Initializing..." lines
            r = simulator.Robotarium(
                number_of_robots=ic.shape[1], show_figure=False, sim_in_real_time=False, initial_conditions=ic
            )
    except RobotariumError:
        return None
    finally:
        simulator.INITIALIZATION_STEP_LIMIT = saved
    return float(r.iterations * r.TIME_STEP)
