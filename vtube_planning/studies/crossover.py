"""The crossover: where the planned swarm passes sooner than the best unplanned one, and where it is safer.

A crossover campaign flies, in each robot model, the plan and the constant-speed unplanned swarms (3.5 m/s and
v_max) through a family of tubes (the ``narrowest_m`` axis: `vtube_planning.studies.study.narrowed`) at several
swarm sizes. Per cell (scene, narrowest half-width, N, setting), `crossover_cells` takes the *best* unplanned mode,
the one of the two with the shorter mean passing time over the seeds (a mode with a run that did not complete is
never the best, unless both have one), and reads the campaign's own paired test of "planning - best" from
`paired_table` (its families, its verdict rule): passing time (T) and minimum distance (D), beside the collision
pairs of both over all seeds. The plan *wins* a cell where T holds (shorter) and it had no collision in any seed;
it is *safer* where D holds (a larger minimum distance) and it had no more collision pairs than the best.
`crossover_markdown` is the table the report adds (`campaign_report_text`), `study_plots.crossover_figure` its
figure.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from vtube_planning.studies.campaign import Campaign
from vtube_planning.studies.judging import Judging
from vtube_planning.studies.stats import NO_VERDICT, NOT_REPLICATED, NOT_SHOWN
from vtube_planning.studies.study_report import CELL_AXES, paired_table, report_text, setting_text

PLANNED = 'planning'
UNPLANNED = ('no planning', 'no planning at v_max')
"""The constant-speed unplanned modes the plan is held against (3.5 m/s, v_max)."""
SIGNS = {'holds': '+', NOT_SHOWN: '=', 'reversed': '-', NOT_REPLICATED: '~', NO_VERDICT: '?'}
"""A verdict's sign, as in the report's verdict rows; 'n/a' where no test was made (a run did not complete)."""


def is_crossover(campaign: Campaign) -> bool:
    """Whether a campaign is a crossover: it flies a family of tubes (a ``narrowest_m`` axis) with the plan and an
    unplanned mode."""
    return any(
        'narrowest_m' in grid and PLANNED in grid.get('mode', ()) and set(UNPLANNED) & set(grid.get('mode', ()))
        for grid in campaign.grids
    )


def _key(row: Mapping[str, Any]) -> tuple[Any, ...]:
    return tuple(row.get(axis) for axis in CELL_AXES)


def _mean_time(rows: list[dict[str, Any]]) -> float:
    """The mean passing time of a mode's runs; infinite when one did not complete (NaN time)."""
    times = np.array([r['passing_time_s'] for r in rows], dtype=float)
    return math.inf if not np.all(np.isfinite(times)) else float(times.mean())


def crossover_cells(rows: list[dict[str, Any]], judging: Judging) -> list[dict[str, Any]]:
    """Per cell with the plan and an unplanned mode (module doc): scene, narrowest_m, n_robots, setting, seeds,
    best (the best unplanned mode), difference_s (planning - best, mean over the paired seeds; NaN without a test),
    time and distance (the verdicts of T and D, None without a test), planned_collisions and best_collisions (pairs,
    all seeds), wins, safer."""
    table = paired_table(rows, judging)
    cells = []
    for key in dict.fromkeys(_key(r) for r in rows):
        sel = [r for r in rows if _key(r) == key]
        planned = [r for r in sel if r['mode'] == PLANNED]
        modes = {m: [r for r in sel if r['mode'] == m] for m in UNPLANNED}
        modes = {m: runs for m, runs in modes.items() if runs}
        if not planned or not modes:
            continue
        best = min(modes, key=lambda m: (_mean_time(modes[m]), UNPLANNED.index(m)))
        tests = {p['metric']: p for p in table if _key(p) == key and (p['a'], p['b']) == (PLANNED, best)}
        time, distance = (tests[m]['verdict'] if m in tests else None for m in ('passing_time_s', 'min_distance_m'))
        mine, theirs = (sum(int(r['collision_pairs']) for r in runs) for runs in (planned, modes[best]))
        first = sel[0]
        cells.append(
            {
                'scene': first['scene'],
                'narrowest_m': first.get('narrowest_m', 0.0),
                'n_robots': first['n_robots'],
                'setting': setting_text(first),
                'seeds': len(planned),
                'best': best,
                'difference_s': tests['passing_time_s']['estimate'].value if time else math.nan,
                'time': time,
                'distance': distance,
                'planned_collisions': mine,
                'best_collisions': theirs,
                'wins': time == 'holds' and mine == 0,
                'safer': distance == 'holds' and mine <= theirs,
            }
        )
    return cells


def sign(verdict: str | None) -> str:
    """A verdict's sign (SIGNS), 'n/a' for none."""
    return 'n/a' if verdict is None else SIGNS[verdict]


def crossover_markdown(cells: list[dict[str, Any]]) -> str:
    """The report's crossover section: a row per cell of `crossover_cells`."""
    lines = [
        '## The crossover: the plan against the best unplanned swarm',
        '',
        (
            'Per cell, the best unplanned swarm is the one of no planning (3.5 m/s) and no planning at v_max with the '
            'shorter mean passing time; T and D are the verdicts of planning - best above (+: the plan is faster, '
            'resp. keeps a larger minimum distance; =: not shown; -: reversed; ?: no verdict; n/a: a run did not '
            'complete). The plan wins where T is + with 0 collision pairs over all seeds, and is safer where D is + '
            'with no more collision pairs than the best.'
        ),
        '',
        (
            '| setting | scene | narrowest half-width [m] | N | best unplanned | planning - best, time [s] | T | D '
            '| collision pairs (planning / best) | plan wins | plan safer |'
        ),
        '|---|---|---|---|---|---|---|---|---|---|---|',
    ]
    for c in cells:
        difference = 'n/a' if math.isnan(c['difference_s']) else f'{c["difference_s"]:+.2f}'
        lines.append(
            f'| {c["setting"]} | {c["scene"]} | {c["narrowest_m"]:g} | {c["n_robots"]} | {c["best"]} | {difference} '
            f'| {sign(c["time"])} | {sign(c["distance"])} | {c["planned_collisions"]} / {c["best_collisions"]} '
            f'| {"yes" if c["wins"] else "no"} | {"yes" if c["safer"] else "no"} |'
        )
    return '\n'.join(lines) + '\n'


def campaign_report_text(
    campaign: Campaign, rows: list[dict[str, Any]], missing: int, made: list[dict[str, Any]]
) -> str:
    """A campaign's ``report.md``: `report_text`, and for a crossover campaign (`is_crossover`) its section."""
    text = report_text(campaign.name, rows, missing, campaign.judging, made)
    if not is_crossover(campaign):
        return text
    return f'{text}\n{crossover_markdown(crossover_cells(rows, campaign.judging))}'
