"""Planned against unplanned on a Robotarium scene over several seeds of the V2 initialization.

``vtube robotarium compare SCENE --seeds N`` (seeds 0..N-1, or a range like 10-19) prints (and writes) the table
the Robotarium comparison pages show (docs/robotarium_compare/): per mode, the
mean and the range over seeds of the passing time, the minimum distance, the tube violations (bodies), the
safety filter's total intervention, the speed band, and the plan tracking per phase. The seed drives the
initialization (charger slots, deadlock escapes), so the runs differ in where the robots really start.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Collection
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
from vtube_planning.studies.judging import confirmed, detectable_text, judge
from vtube_planning.studies.stats import NOT_SHOWN, nonzero_count, paired_difference, relative, signed_rank_p
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
BETTER = {
    'passing_time_s': 'lower',
    'min_distance_m': 'higher',
    'tube_violation_steps': 'lower',
    'intervention_m': 'lower',
    'band_percent': 'higher',
    'approach_percent': 'lower',
    'dip_percent': 'lower',
    'testbed_errors': 'lower',
}
"""The measures compared as claims ("planned is better"), and which way is better; the others are timings."""


@dataclass(frozen=True)
class ComparisonRow:
    """One run of the comparison: its seed and mode, the measures of ``COLUMNS`` (None: did not happen) and why
    the flight failed (`flight_failures`; empty: it succeeded)."""

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
    the simulator flies ``testbed_model`` (`robotarium_exp.rps.testbed_model.testbed_model`)."""
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


def paired_table(rows: list[ComparisonRow], confirm_seeds: Collection[int] = ()) -> str:
    """Markdown: per measure of BETTER, planned - unplanned paired by seed (the same initialization draws), its
    interval, effect and signed-rank p-value, Holm-adjusted within its family (`vtube_planning.studies.judging`: no
    family declared, each measure is its own), and the verdict (`vtube_planning.studies.stats`), over every seed; with
    ``confirm_seeds`` held out, on the other seeds, the claims found tested again on those, and both's verdict."""
    held = set(confirm_seeds)
    found = judge(_tests([r for r in rows if r.seed not in held]), ())
    if held:
        found = confirmed(found, _tests([r for r in rows if r.seed in held]), (), lambda t: t['metric'])
    head = '| planned - unplanned, same seeds | ' + (
        'seeds found on | held-out seeds | verdict |' if held else 'verdict |'
    )
    lines = [
        (
            'Each measure is its own family (one claim each, no family declared). Not shown: the seeds could not '
            'tell planned from unplanned (not evidence that they are alike); beside it, the shift of the mean '
            'difference, in SDs of the differences and in units, that they find with 80 % power. No verdict: '
            'fewer than 6 seeds, or too few non-zero differences for any claim to reach 0.05.'
        ),
        '',
        head,
        '|---|' + '---|' * (3 if held else 1),
    ]
    by_metric = {t['metric']: t for t in found}
    for title, key, _ in COLUMNS:
        if key not in by_metric:
            continue
        t = by_metric[key]
        if held:
            again = t['confirmation']
            fresh = 'not tested again (no claim found)' if again is None else _test_text(again, again['verdict'])
            lines.append(f'| {title} | {_test_text(t, t["discovery_verdict"])} | {fresh} | **{t["verdict"]}** |')
        else:
            lines.append(f'| {title} | {_test_text(t, t["verdict"], bold=True)} |')
    return '\n'.join(lines) + '\n'


def _tests(rows: list[ComparisonRow]) -> list[dict[str, Any]]:
    """Per measure of BETTER with two or more complete pairs: its paired test, not yet judged (`judge`)."""
    tests = []
    for key, better in BETTER.items():
        pairs: dict[int, dict[bool, float]] = {}
        for r in rows:
            value = getattr(r, key)
            if value is not None and np.isfinite(value):
                pairs.setdefault(r.seed, {})[r.planned] = float(value)
        both = [(v[True], v[False]) for v in pairs.values() if len(v) == 2]
        if len(both) >= 2:
            planned, unplanned = np.array(both).T
            estimate, d = paired_difference(planned, unplanned), planned - unplanned
            tests.append(
                {'a': 'planned', 'b': 'unplanned', 'metric': key, 'better': better, 'estimate': estimate}
                | {'p': signed_rank_p(d), 'nonzero': nonzero_count(d), 'sd': float(np.std(d, ddof=1))}
                | {'relative': relative(estimate.value, unplanned)}
            )
    return tests


def _test_text(test: dict[str, Any], verdict: str, *, bold: bool = False) -> str:
    """A measure's difference, interval, effect, adjusted p-value, seeds and verdict (where not shown, with the
    shift its seeds find at 80 % power)."""
    effect = test['relative']
    shown = '' if math.isnan(effect) else f' ({effect:+.0%})'
    p_text = 'p n/a' if math.isnan(test['p_holm']) else f'p {test["p_holm"]:.3g}'
    power = f' ({detectable_text(test)})' if verdict == NOT_SHOWN else ''
    said = f'**{verdict}**' if bold else verdict
    return f'{test["estimate"].text(3)}{shown}, {p_text}, {test["estimate"].n} seeds: {said}{power}'


def failed_runs(rows: list[ComparisonRow]) -> tuple[str, ...]:
    """The runs that failed, one line each: the seed, the mode and why."""
    return tuple(
        f'seed {row.seed}, {"planned" if row.planned else "unplanned"}: {"; ".join(row.failures)}'
        for row in rows
        if row.failures
    )


def _percent(value: float | None) -> float | None:
    return None if value is None else 100.0 * value
