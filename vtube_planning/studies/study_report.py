"""Reports of a study's grid: its cells, paired comparisons and verdicts, and the comparisons over random maps.

`grid_markdown` reports each cell of a grid with bootstrap intervals and the paired differences of
COMPARISONS (`vtube_planning.studies.stats`); over random maps, `map_differences` takes the maps as the sample.
Rows are those of `run_point` with their `Point`'s fields;
the paper's comparison per scene is in `vtube_planning.studies.paper_report`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vtube_planning.provenance import made_counts, made_text
from vtube_planning.studies.judging import POOLED, Family, Judging, confirmed, detectable_text, families_text, judge
from vtube_planning.studies.seeds import seeds_text
from vtube_planning.studies.stats import (
    ALPHA,
    MIN_SEEDS,
    NO_VERDICT,
    NOT_REPLICATED,
    NOT_SHOWN,
    Estimate,
    cell_values,
    mean_interval,
    nonzero_count,
    paired_difference,
    relative,
    signed_rank_p,
)
from vtube_planning.studies.study import physics_text

COMPARISONS = (
    ('planning', 'no planning', "the paper's comparison"),
    ('planning', 'no planning at v_max', 'the plan against the fastest constant speed'),
    ('planning (relaxed)', 'no planning', "the plan with the unplanned swarm's freedom against 3.5 m/s"),
    ('planning (relaxed)', 'no planning at v_max', "the plan with the unplanned swarm's freedom against v_max"),
    ('planning', 'planning without (p7)', 'what the pre-expansion (p7) buys'),
    ('planning', 'planned speed, (a3) off', 'what (a3) buys on top of the planned speed'),
    ('replanning every 0.5 s', 'planning', 'what replanning online buys'),
    ('constant speed, (a3) to rho_d', 'no planning', 'what (a3) buys without a plan'),
)
"""Paired comparisons of the grid report: mode a against mode b on the same seeds, and what the difference means."""
CLAIMS = (('passing_time_s', 'lower', 'passing time [s]'), ('min_distance_m', 'higher', 'min distance [m]'))


CELL_AXES: tuple[str, ...] = ('scene', 'map', 'map_seed', 'map_clutter', 'map_width_m', 'n_robots', 'model')
CELL_AXES += ('controller', 'saturation', 'pose_noise_m', 'latency_steps', 'lag_s', 'compensation', 'failure')
CELL_AXES += ('dropout', 'narrowest_m')
"""What a row's mode is compared within (a cell): every field of `Point` but the mode and the seed."""


def _cell(row: Mapping[str, Any]) -> tuple[Any, ...]:
    return tuple(row.get(axis) for axis in CELL_AXES)


def place_text(row: dict[str, Any]) -> str:
    """Where a cell flies: its scene (narrowed, `vtube_planning.studies.study.narrowed`), its random map if any."""
    scene = f'Scene {row["scene"]}' + (f', narrowest {row["narrowest_m"]:g} m' if row.get('narrowest_m') else '')
    if row.get('map') in (None, 'none'):
        return scene
    return f'{scene} on {_population_text(row)} map {row["map_seed"]}'


def _population_text(row: dict[str, Any]) -> str:
    """The maps a random map is drawn from: its family and difficulty."""
    opening = f', opening {row["map_width_m"]:g} m' if row['map'] == 'bottleneck' else ''
    return f'{row["map"]} (clutter {row["map_clutter"]}{opening})'


def setting_text(row: dict[str, Any]) -> str:
    """A cell's setting in words, scene and N left out: the robot model, the saturation, the controller (unless the
    law) and the faults that are on."""
    words = [f'{row["model"]} model', f'{row["saturation"]} sat']
    if row.get('controller') not in (None, 'law'):
        words.append(f'{row["controller"]} controller')
    if row.get('pose_noise_m'):
        words.append(f'pose noise {row["pose_noise_m"]:g} m')
    if row.get('latency_steps'):
        words.append(f'latency {row["latency_steps"]} periods')
    if row.get('lag_s'):
        words.append(f'lag {row["lag_s"]:g} s')
    if row.get('compensation') not in (None, 'none'):
        words.append(f'compensation {row["compensation"]}')
    if row.get('failure') not in (None, 'none'):
        words.append(f'a robot fails ({row["failure"]})')
    if row.get('dropout'):
        words.append(f'dropout {row["dropout"]:g}')
    return ', '.join(words)


def verdict_summary(table: list[dict[str, Any]], held_out: bool = False) -> str:
    """Where each comparison's claim holds: per setting (`setting_text`), in how many cells (scene, N) the
    paired test of `paired_table` says a beats b (+), cannot tell (=, not shown) or b beats a (-), where the
    held-out seeds did not confirm it (~) and where there were too few seeds for a verdict (?), for each metric
    of CLAIMS; then the families the tests were adjusted in (`families_text`)."""
    settings = list(dict.fromkeys(setting_text(p) for p in table))
    compared = [c for c in COMPARISONS if any((p['a'], p['b']) == c[:2] for p in table)]
    cells = '(scene, map, N)' if any(r.get('map') not in (None, 'none') for r in table) else '(scene, N)'
    cells = cells.replace('scene', 'scene, narrowest half-width') if any(p.get('narrowest_m') for p in table) else cells
    seeds = (
        'on the seeds found on, the claims found then tested again on the held-out seeds (~: not confirmed there)'
        if held_out
        else 'over all the seeds of the campaign, pooled'
    )
    lines = [
        (
            f'Cells {cells} where a beats b (+), where that is not shown (=: a and b not told apart, which is not '
            f'evidence that they are alike), or b beats a (-): the paired signed-rank test {seeds}, '
            f'Holm-adjusted within each family of claims below, below {ALPHA:g} and the 95 % interval on that '
            f'side; ?: no verdict, from fewer than {MIN_SEEDS} seeds or from too few non-zero differences for the '
            f'family (no claim of it could reach {ALPHA:g} after the adjustment: more seeds, or a smaller family). '
            'T: passing time (shorter is better), D: minimum distance (larger is better).'
        ),
        '',
        '| setting | ' + ' | '.join(f'{a} - {b} ({meaning})' for a, b, meaning in compared) + ' |',
        '|---|' + '---|' * len(compared),
    ]
    for setting in settings:
        cols = []
        for a, b, _ in compared:
            counts = []
            for (metric, _, _), letter in zip(CLAIMS, 'TD', strict=True):
                found = [
                    p['verdict']
                    for p in table
                    if (p['a'], p['b'], p['metric']) == (a, b, metric) and setting_text(p) == setting
                ]
                text = ' '.join(f'{sign}{found.count(v)}' for sign, v in _SIGNS if found.count(v) or sign in '+=-')
                counts.append(f'{letter} {text}')
            cols.append(', '.join(counts))
        lines.append(f'| {setting} | ' + ' | '.join(cols) + ' |')
    families = (
        'The families (declared in the campaign, one per claim; the claims no family takes: one family per '
        "comparison and metric), with the shift of the paired differences' mean, in their standard deviations "
        "(SD), that the signed-rank test finds with 80 % power at the family's level (0.05 over its size, normal "
        "differences; in the cells, also in the metric's units):"
    )
    return '\n'.join([*lines, '', families, '', families_text(table)] if table else lines) + '\n'


_SIGNS = (('+', 'holds'), ('=', NOT_SHOWN), ('-', 'reversed'), ('~', NOT_REPLICATED), ('?', NO_VERDICT))


def map_differences(rows: list[dict[str, Any]], families: tuple[Family, ...] = ()) -> list[dict[str, Any]]:
    """Over the random maps of each population (scene, N, setting, map family and difficulty), the comparisons of
    COMPARISONS on each metric of CLAIMS: the mean over maps of each map's mean paired difference (a - b over its
    seeds) with its 95 % bootstrap interval and signed-rank test over maps (the maps are the sample: the claim is
    about the family, not one map), Holm-adjusted within its family (`judge`), and verdict; ``per_map``: each map's
    mean difference over all its seeds (none held out: the maps are the sample), and ``counts``: where the maps' own
    paired intervals lie. A map whose runs did not all complete is left out of that comparison."""
    out = []
    mapped = [r for r in rows if r.get('map') not in (None, 'none')]
    for population in dict.fromkeys(_population(r) for r in mapped):
        sel = [r for r in mapped if _population(r) == population]
        maps = [[r for r in sel if r['map_seed'] == seed] for seed in dict.fromkeys(r['map_seed'] for r in sel)]
        for a, b, _ in COMPARISONS:
            for metric, better, _ in CLAIMS:
                pairs = [(cell_values(m, metric, mode=a), cell_values(m, metric, mode=b)) for m in maps]
                pairs = [(x, y) for x, y in pairs if x.size and x.size == y.size and np.all(np.isfinite(x - y))]
                if len(pairs) < 2:
                    continue
                per_map = [float(np.mean(x - y)) for x, y in pairs]
                own = [_direction(d, better) for d in (_paired(x, y) for x, y in pairs) if d is not None]
                counts = ' '.join(f'{s}{own.count(s)}' for s in '+=-')
                first = sel[0] | {'a': a, 'b': b, 'metric': metric, 'better': better, 'per_map': per_map}
                tested = {'estimate': mean_interval(per_map), 'p': signed_rank_p(per_map)}
                out.append(
                    first
                    | {'counts': counts, 'nonzero': nonzero_count(per_map), 'sd': float(np.std(per_map, ddof=1))}
                    | tested
                )
    return judge(out, families)


def _direction(difference: Estimate, better: str) -> str:
    """Which side of zero a map's own interval lies on: a beats b (+), cannot tell (=), b beats a (-)."""
    if not difference.excludes_zero():
        return '='
    return '+' if (difference.value > 0) == (better == 'higher') else '-'


def _population(row: dict[str, Any]) -> tuple[Any, ...]:
    return row['scene'], row['n_robots'], row['map'], row['map_clutter'], row['map_width_m'], setting_text(row)


def map_summary(rows: list[dict[str, Any]], families: tuple[Family, ...] = ()) -> str:
    """The table of `map_differences` (empty for rows without random maps), and its families."""
    found = map_differences(rows, families)
    if not found:
        return ''
    lines = [
        (
            'Over the random maps (each map the mean of its seeds; 95 % interval and signed-rank test over maps, '
            "Holm-adjusted p within each family), and how many maps' own intervals lie on a's side (+), across "
            "zero (=) or on b's (-). The families, with the shift (in SDs of the maps' differences) found with "
            "80 % power at the family's level:"
        ),
        '',
        families_text(found),
        '| maps | setting | comparison (a - b) | ' + ' | '.join(t for _, _, t in CLAIMS) + ' |',
        '|---|---|---|' + '---|' * len(CLAIMS),
    ]
    for head in dict.fromkeys((*_population(f), f['a'], f['b']) for f in found):
        match = {f['metric']: f for f in found if (*_population(f), f['a'], f['b']) == head}
        f = next(iter(match.values()))
        cols = [f'{_test_text(g)} ({g["counts"]})' for g in match.values()]
        maps = f'{len(f["per_map"])} {_population_text(f)} maps, scene {f["scene"]}, N = {f["n_robots"]}'
        lines.append(f'| {maps} | {setting_text(f)} | {f["a"]} - {f["b"]} | ' + ' | '.join(cols) + ' |')
    return '\n'.join(lines) + '\n'


def mode_summary(rows: list[dict[str, Any]]) -> str:
    """Per setting and mode, over every scene, N and seed: collision pairs and the runs with any, the runs that did
    not complete, and the range over cells (scene, N) of the share of robot-steps moving backwards (the columns
    whose metrics the rows hold)."""
    columns = [c for c in _MODE_COLUMNS if c[0] in rows[0]]
    lines = [
        physics_text(dict.fromkeys(r['mode'] for r in rows)),
        '',
        'Per setting and mode, over all cells and seeds:',
        '',
        '| setting | mode | ' + ' | '.join(header for _, header, _ in columns) + ' |',
        '|---|---|' + '---|' * len(columns),
    ]
    for setting in dict.fromkeys(setting_text(r) for r in rows):
        for mode in dict.fromkeys(r['mode'] for r in rows):
            sel = [r for r in rows if r['mode'] == mode and setting_text(r) == setting]
            if sel:
                lines.append(f'| {setting} | {mode} | ' + ' | '.join(text(sel) for _, _, text in columns) + ' |')
    return '\n'.join(lines) + '\n'


def _backwards_range(sel: list[dict[str, Any]]) -> str:
    cells = dict.fromkeys((r['scene'], r['n_robots']) for r in sel)
    means = [np.mean([r['reversing_share'] for r in sel if (r['scene'], r['n_robots']) == c]) for c in cells]
    return f'{min(means):.1%}-{max(means):.1%}'


_MODE_COLUMNS: tuple[tuple[str, str, Callable[[list[dict[str, Any]]], str]], ...] = (
    (
        'collision_pairs',
        'collision pairs (runs with any / runs)',
        lambda sel: (
            f'{sum(r["collision_pairs"] for r in sel)} ({sum(r["collision_pairs"] > 0 for r in sel)}/{len(sel)})'
        ),
    ),
    ('completed', 'runs not completed', lambda sel: str(sum(not r['completed'] for r in sel))),
    ('reversing_share', 'in-tube robot-steps moving backwards (lowest-highest cell mean)', _backwards_range),
)
_CELL_COLUMNS: tuple[tuple[str, str, Callable[[NDArray[np.float64]], str]], ...] = (
    ('passing_time_s', 'passing time [s]', lambda v: _interval(v, 2)),
    ('min_distance_m', 'min distance [m]', lambda v: _interval(v, 3)),
    ('min_distance_m', '5 % min distance [m]', lambda v: f'{np.quantile(v, 0.05):.3f}'),
    ('collision_pairs', 'collisions (pairs, all seeds)', lambda v: f'{int(v.sum())}'),
    ('passed_share', 'robots through (mean)', lambda v: f'{np.mean(v):.0%}'),
    ('tube_violation_steps', 'tube violations (robot-steps, mean)', lambda v: f'{np.mean(v):.0f}'),
    ('density_error_per_m2', 'density error [1/m^2]', lambda v: _interval(v, 3)),
    ('reversing_share', 'reversing robot-steps', lambda v: f'{np.mean(v):.1%}'),
)
"""The columns of the reports: metric, header, and how a selection's values are written."""


def grid_markdown(rows: list[dict[str, Any]], judging: Judging = POOLED) -> str:
    """A study's report: where each comparison holds (`verdict_summary`), collisions per mode
    (`mode_summary`), then per cell (scene, N, setting) each mode's means with 95 % bootstrap intervals and
    the paired differences of COMPARISONS with their intervals, effect sizes, adjusted p-values and verdicts
    (`paired_table`, as ``judging`` says: its families, and seeds held out or not)."""
    table = paired_table(rows, judging)
    held = bool(judging.held_out)
    lines = [verdict_summary(table, held), map_summary(rows, judging.families), mode_summary(rows)]
    for cell in dict.fromkeys(_cell(r) for r in rows):
        sel = [r for r in rows if _cell(r) == cell]
        modes = list(dict.fromkeys(r['mode'] for r in sel))
        seeds = sorted({r['seed'] for r in sel})
        first = sel[0]
        columns = [c for c in _CELL_COLUMNS if c[0] in first]
        lines += [
            f'### {place_text(first)}, N = {first["n_robots"]}, {setting_text(first)} (seeds {seeds_text(seeds)})',
            '',
            '| mode | ' + ' | '.join(header for _, header, _ in columns) + ' |',
            '|---|' + '---|' * len(columns),
        ]
        for mode in modes:
            cols = [text(cell_values(sel, metric, mode=mode)) for metric, _, text in columns]
            lines.append(f'| {mode} | ' + ' | '.join(cols) + ' |')
        differences = [p for p in table if _cell(p) == cell]
        compared = [c for c in COMPARISONS if any((p['a'], p['b']) == c[:2] for p in differences)]
        if compared:
            seeds_note = ' (seeds found on; held-out seeds)' if held else ''
            lines += [
                '',
                f'| comparison (a - b, same seeds{seeds_note}) | ' + ' | '.join(t for _, _, t in CLAIMS) + ' |',
                '|---|---|---|',
            ]
        for a, b, meaning in compared:
            found = {p['metric']: p for p in differences if (p['a'], p['b']) == (a, b)}
            cols = [_claim_text(found[m]) if m in found else 'n/a' for m, _, _ in CLAIMS]
            lines.append(f'| {a} - {b} ({meaning}) | ' + ' | '.join(cols) + ' |')
        lines.append('')
    return '\n'.join(lines)


def report_text(
    name: str, rows: list[dict[str, Any]], missing: int, judging: Judging, made: list[dict[str, Any]]
) -> str:
    """A campaign's ``report.md``: what it holds and what made its runs (``made``: the entries of its
    ``provenance.json``), then `grid_markdown`."""
    head = f'Campaign {name!r}: {len(rows)} runs'
    if missing:
        head += f' ({missing} of the grid missing or failed: the tables are partial; rerun the campaign to finish)'
    lines = [f'{head}.', '']
    lines += [f'- {count} runs {made_text(entry)}' for count, entry in zip(made_counts(made, len(rows)), made)]
    if made:
        lines.append('')
    return '\n'.join([*lines, grid_markdown(rows, judging)])


def _test_text(test: dict[str, Any]) -> str:
    """A paired difference, its interval, its effect size, its adjusted p-value and its verdict (where not shown,
    with the shift its seeds would have found: `detectable_text`)."""
    effect = '' if math.isnan(test.get('relative', math.nan)) else f' ({test["relative"]:+.0%})'
    p = 'p n/a' if math.isnan(test['p_holm']) else f'p {test["p_holm"]:.3g}'
    found = test.get('discovery_verdict', test['verdict'])
    power = f' ({detectable_text(test)})' if found == NOT_SHOWN else ''
    return f'{test["estimate"].text(3)}{effect}, {p}: {found}{power}'


def _claim_text(test: dict[str, Any]) -> str:
    """`_test_text`, and with held-out seeds theirs and the verdict of both."""
    if 'discovery_verdict' not in test:
        return _test_text(test)
    again = test.get('confirmation')
    fresh = 'not tested again (no claim found)' if again is None else _test_text(again)
    return f'{_test_text(test)}; {fresh} => **{test["verdict"]}**'


def paired_table(rows: list[dict[str, Any]], judging: Judging = POOLED) -> list[dict[str, Any]]:
    """Per cell (CELL_AXES), the paired differences of COMPARISONS on each metric of CLAIMS: dicts with the cell's
    fields, a, b, metric, estimate (an `Estimate`), p (signed-rank), relative (the effect as a share of b's mean)
    and what `judge` adds in ``judging``'s families: family, p_holm, verdict, detectable.

    Every seed is pooled, unless ``judging`` holds seeds out: then all that is computed on the other seeds, and the
    claims found are tested again on the held-out ones (`confirmed`: ``confirmation``, ``discovery_verdict`` and
    both's ``verdict``). Comparisons whose modes are missing, or whose runs did not all complete, are left out."""
    held = set(judging.held_out)
    found = _judged([r for r in rows if r['seed'] not in held], judging.families)
    if not held:
        return found
    again = _tests([r for r in rows if r['seed'] in held])
    return confirmed(found, again, judging.families, _test_key)


def _test_key(test: Mapping[str, Any]) -> tuple[Any, ...]:
    return (*_cell(test), test['a'], test['b'], test['metric'])


def _judged(rows: list[dict[str, Any]], families: tuple[Family, ...]) -> list[dict[str, Any]]:
    """The paired tests of `paired_table` on ``rows``, judged in ``families``."""
    return judge(_tests(rows), families)


def _tests(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The paired tests of `paired_table` on ``rows``, not yet judged."""
    tests = []
    for cell in dict.fromkeys(_cell(r) for r in rows):
        sel = [r for r in rows if _cell(r) == cell]
        fields = dict(zip(CELL_AXES, cell, strict=True))
        for a, b, _ in COMPARISONS:
            for metric, better, _ in CLAIMS:
                if metric not in sel[0]:
                    continue
                x, y = cell_values(sel, metric, mode=a), cell_values(sel, metric, mode=b)
                diff = _paired(x, y)
                if diff is not None:
                    found = {'estimate': diff, 'p': signed_rank_p(x - y), 'relative': relative(diff.value, y)}
                    found |= {'nonzero': nonzero_count(x - y), 'sd': float(np.std(x - y, ddof=1))}
                    tests.append(fields | {'a': a, 'b': b, 'metric': metric, 'better': better} | found)
    return tests


def _interval(values: NDArray[np.float64], digits: int) -> str:
    finite = values[np.isfinite(values)]
    if finite.size < values.size:
        return f'{finite.size} of {values.size} completed'
    return mean_interval(values).text(digits) if values.size > 1 else f'{values[0]:.{digits}f}'


def _paired(a: NDArray[np.float64], b: NDArray[np.float64]) -> Estimate | None:
    if a.size < 2 or a.size != b.size or not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        return None
    return paired_difference(a, b)
