"""Planned against unplanned on a Robotarium scene over several seeds of the V2 initialization.

``vtube robotarium compare SCENE --seeds N`` (seeds 0..N-1, or a range like 10-19) prints (and writes) the table
the README quotes: per mode, the
mean and the range over seeds of the passing time, the minimum distance, the tube violations (bodies), the
safety filter's total intervention, the speed band, and the plan tracking per phase. The seed drives the
initialization (charger slots, deadlock escapes), so the runs differ in where the robots really start.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from robotarium_exp.experiment import ExperimentConfig, run_experiment
from robotarium_exp.rps.robotarium import Robotarium
from robotarium_exp.rps_alias import seed_rps
from robotarium_exp.tracking import plan_tracking
from robotarium_exp.verdict import flight_failures
from vtube_planning.geometry.scene import Scene
from vtube_planning.planning.plan import Plan
from vtube_planning.swarm.metrics import strict_json

COLUMNS = (
    ('passing time [s]', 'passing_time_s', '.1f'),
    ('min distance [m]', 'min_distance_m', '.3f'),
    ('tube violations (bodies)', 'tube_violation_steps', '.0f'),
    ('filter intervention [m]', 'intervention_m', '.2f'),
    ('speed band [%]', 'band_percent', '.1f'),
    ('density error, approach [%]', 'approach_percent', '.0f'),
    ('density error, dip [%]', 'dip_percent', '.0f'),
    ('expansion starts [s]', 'expansion_start_s', '.1f'),
    ('front at the narrowing [s]', 'front_at_narrowing_s', '.1f'),
    ('testbed errors', 'testbed_errors', '.0f'),
)


@dataclass(frozen=True)
class ComparisonRow:
    """One run of the comparison: its seed and mode, the measures of ``COLUMNS`` (None: did not happen) and why
    the flight failed (:func:`~robotarium_exp.verdict.flight_failures`; empty: it succeeded)."""

    seed: int
    planned: bool
    passing_time_s: float
    min_distance_m: float
    tube_violation_steps: int
    intervention_m: float
    band_percent: float
    approach_percent: float | None
    dip_percent: float | None
    expansion_start_s: float | None
    front_at_narrowing_s: float | None
    testbed_errors: int
    failures: tuple[str, ...] = ()

    def to_json(self) -> dict[str, Any]:
        """The row as strict JSON: NaN and infinities become None."""
        json: dict[str, Any] = strict_json(asdict(self))
        return json


def compare(
    scene: Scene,
    plan: Plan,
    seeds: list[int],
    run_done: Callable[[], None] | None = None,
    testbed_model: str = 'ideal',
) -> list[ComparisonRow]:
    """One row per seed and mode (planned, unplanned); ``run_done`` is called after each run (a progress bar);
    the simulator flies ``testbed_model`` (:func:`robotarium_exp.rps.testbed_model.testbed_model`)."""
    rows = []
    for seed in seeds:
        for planned in (True, False):
            seed_rps(seed)  # the same V2 initialization draws for both modes
            config, kwargs = ExperimentConfig(planning=planned), {'testbed_model': testbed_model}
            result = run_experiment(Robotarium, scene, plan if planned else None, config, robotarium_kwargs=kwargs)
            tracked = plan_tracking(result.arrays, plan, scene)
            rows.append(
                ComparisonRow(
                    seed=seed,
                    planned=planned,
                    passing_time_s=result.metrics.passing_time_s,
                    min_distance_m=result.metrics.min_distance_m,
                    tube_violation_steps=result.metrics.tube_violation_steps,
                    intervention_m=result.barrier.intervention_m,
                    band_percent=100.0 * result.barrier.band_share,
                    approach_percent=_percent(tracked.approach.density_error_mean),
                    dip_percent=_percent(tracked.dip.density_error_mean),
                    expansion_start_s=tracked.expansion_start_s,
                    front_at_narrowing_s=tracked.front_at_narrowing_s,
                    testbed_errors=result.errors.too_close + result.errors.outside + result.errors.actuator,
                    failures=flight_failures(result),
                )
            )
            if run_done is not None:
                run_done()
    return rows


def comparison_table(rows: list[ComparisonRow]) -> str:
    """Markdown: one row per measure, planned and unplanned as 'mean [min, max]' over the seeds."""
    lines = ['| measure | planned | unplanned |', '|---|---|---|']
    for title, key, fmt in COLUMNS:
        cells = []
        for planned in (True, False):
            values = [getattr(r, key) for r in rows if r.planned is planned and getattr(r, key) is not None]
            if not values:
                cells.append('never' if key == 'expansion_start_s' else '–')
                continue
            cells.append(f'{np.mean(values):{fmt}} [{min(values):{fmt}}, {max(values):{fmt}}]')
        lines.append(f'| {title} | ' + ' | '.join(cells) + ' |')
    return '\n'.join(lines) + '\n'


def failed_runs(rows: list[ComparisonRow]) -> tuple[str, ...]:
    """The runs that failed, one line each: the seed, the mode and why."""
    return tuple(
        f'seed {row.seed}, {"planned" if row.planned else "unplanned"}: {"; ".join(row.failures)}'
        for row in rows
        if row.failures
    )


def _percent(value: float | None) -> float | None:
    return None if value is None else 100.0 * value
