"""How long V2's initializer takes to bring robots to given initial conditions: its distribution over seeds.

The bundled simulator runs V2's initializer with V2's draws (:func:`robotarium_exp.rps_alias.seed_rps`), so the
distribution is V2's up to the barrier QP's tolerance (``docs/robotarium.md`` §2.6). Used by
``vtube submission check`` to derive the duration to declare, and by ``benchmarks/initializer_durations.py``.
"""

from __future__ import annotations

import contextlib
import io
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

import robotarium_exp.rps.robotarium as simulator
from robotarium_exp.errors import RobotariumError
from robotarium_exp.rps_alias import seed_rps


@dataclass(frozen=True)
class InitializerSample:
    """Durations (s, simulated) of the seeds that finished, and the seeds that did not within the step limit."""

    durations_s: tuple[float, ...]
    stuck_seeds: tuple[int, ...]

    @property
    def runs(self) -> int:
        return len(self.durations_s) + len(self.stuck_seeds)


def initializer_durations(ic: NDArray[np.float64], seeds: Iterable[int], limit: int = 15_000) -> InitializerSample:
    """Run V2's initializer for ``ic`` (3xN) once per seed; a run over ``limit`` steps counts as stuck."""
    done, stuck = [], []
    saved = simulator.INITIALIZATION_STEP_LIMIT
    simulator.INITIALIZATION_STEP_LIMIT = limit
    try:
        for seed in seeds:
            seed_rps(seed)
            try:
                with contextlib.redirect_stdout(io.StringIO()):  # V2's "Initializing..." lines
                    r = simulator.Robotarium(
                        number_of_robots=ic.shape[1], show_figure=False, sim_in_real_time=False, initial_conditions=ic
                    )
            except RobotariumError:
                stuck.append(seed)
                continue
            done.append(r.iterations * r.TIME_STEP)
    finally:
        simulator.INITIALIZATION_STEP_LIMIT = saved
    return InitializerSample(tuple(done), tuple(stuck))
