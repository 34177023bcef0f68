"""Reports of a study: the paper's comparison per scene, and the grid's cells, paired comparisons and verdicts.

The paper's claim, checked per scene on the means over seeds and per seed (:func:`summarise`): with planning the
passing time is shorter, the minimum distance larger, and no two robots collide; against the baselines, planning
passes more safely. :func:`grid_markdown` reports each cell of a grid with bootstrap intervals and the paired
differences of COMPARISONS (:mod:`vtube_planning.stats`). Rows are those of :func:`~vtube_planning.study.run_point`
with their :class:`~vtube_planning.study.Point`'s fields.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vtube_planning.stats import Estimate, cell_values, mean_interval, paired_difference, verdict
from vtube_planning.study import BASELINE_MODES, RunSettings


def summarise(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per scene: means and ranges per mode, and whether the paper's claims hold (on means and per seed)."""
    out = []
    for name in dict.fromkeys(r['scene'] for r in rows):
        entry: dict[str, Any] = {'scene': name}
        per_mode = {}
        modes = list(dict.fromkeys(r['mode'] for r in rows if r['scene'] == name))
        entry['modes'] = modes
        for mode in modes:
            sel = [r for r in rows if r['scene'] == name and r['mode'] == mode]
            passing = np.array([r['passing_time_s'] for r in sel])
            distance = np.array([r['min_distance_m'] for r in sel])
            per_mode[mode] = sel
            entry[mode] = {
                'passing_time_s': float(passing.mean()),
                'passing_time_range_s': [float(passing.min()), float(passing.max())],
                'min_distance_m': float(distance.mean()),
                'min_distance_range_m': [float(distance.min()), float(distance.max())],
                'collision_pairs': int(sum(r['collision_pairs'] for r in sel)),
                'incursion_depth_m': float(max(r['incursion_depth_m'] for r in sel)),
                'nmpc_converged_share': float(np.mean([r['nmpc_converged_share'] for r in sel])),
                'tube_violation_steps': int(sum(r['tube_violation_steps'] for r in sel)),
                'completed': all(r['completed'] for r in sel),
            }
        planned, unplanned = entry['planning'], entry['no planning']
        entry['claim_on_means'] = (
            planned['passing_time_s'] < unplanned['passing_time_s']
            and planned['min_distance_m'] > unplanned['min_distance_m']
            and planned['collision_pairs'] == 0
        )
        pairs = zip(per_mode['planning'], per_mode['no planning'], strict=True)
        entry['claim_per_seed'] = [
            {
                'seed': p['seed'],
                'holds': p['passing_time_s'] < u['passing_time_s']
                and p['min_distance_m'] > u['min_distance_m']
                and p['collision_pairs'] == 0,
            }
            for p, u in pairs
        ]
        entry['safer_than'] = {
            mode: planned['collision_pairs'] < entry[mode]['collision_pairs']
            or (
                planned['collision_pairs'] == entry[mode]['collision_pairs'] == 0
                and planned['min_distance_m'] > entry[mode]['min_distance_m']
            )
            for mode in modes
            if mode in BASELINE_MODES
        }
        out.append(entry)
    return out


def study_markdown(
    summary: list[dict[str, Any]], seeds: list[int], acceleration_limits: bool, settings: RunSettings | None = None
) -> str:
    """The comparison as a Markdown table, with the claim's verdict per scene."""
    settings = settings or RunSettings()
    model = 'with the acceleration limits (3), (4) per robot' if acceleration_limits else "the paper's model"
    lines = [
        (
            f'Scenes with and without planning, Table 1 swarm (N = 20), {model}, dt = {settings.dt_s} s, '
            f'seeds {seeds[0]}..{seeds[-1]} (initial jitter {settings.jitter_m} m). Means over seeds, [min, max].'
        ),
        '',
        (
            '| scene | mode | passing time [s] | min distance [m] | collisions (pairs) | deepest incursion [m] '
            '| tube violations (robot-steps) |'
        ),
        '|---|---|---|---|---|---|---|',
    ]
    for entry in summary:
        for mode in entry['modes']:
            e = entry[mode]
            lo, hi = e['passing_time_range_s']
            dlo, dhi = e['min_distance_range_m']
            lines.append(
                f'| {entry["scene"]} | {mode} | {e["passing_time_s"]:.2f} [{lo:.2f}, {hi:.2f}] | '
                f'{e["min_distance_m"]:.3f} [{dlo:.3f}, {dhi:.3f}] | {e["collision_pairs"]} | '
                f'{e["incursion_depth_m"]:.3f} | {e["tube_violation_steps"]} |'
            )
    lines += ['', "The paper's claim (with planning: shorter passing time, larger minimum distance, no collision):", '']
    for entry in summary:
        held = [c['seed'] for c in entry['claim_per_seed'] if c['holds']]
        failed = [c['seed'] for c in entry['claim_per_seed'] if not c['holds']]
        verdict = 'holds' if entry['claim_on_means'] else 'does not hold'
        detail = f'; per seed it holds for {len(held)} of {len(held) + len(failed)}'
        if failed:
            detail += f' (not for seed {", ".join(map(str, failed))})'
        lines.append(f'- scene {entry["scene"]}: {verdict} on the means{detail}.')
    compared = [entry for entry in summary if entry['safer_than']]
    if compared:
        lines += [
            '',
            (
                'Against the baselines (planning safer: fewer collisions, or none on either side and a '
                'larger minimum distance):'
            ),
            '',
        ]
        for entry in compared:
            for mode, safer in entry['safer_than'].items():
                lines.append(
                    f'- scene {entry["scene"]}, {mode}: {"holds" if safer else "does not hold"} '
                    f'({entry["planning"]["collision_pairs"]} against {entry[mode]["collision_pairs"]} '
                    'collision pairs).'
                )
        solved = [entry for entry in compared if 'nmpc' in entry['modes']]
        if solved:
            lines += ['', "NMPC's solves (IPOPT, every agent every 0.1 s) that converged, mean over seeds:", '']
            lines += [f'- scene {e["scene"]}: {e["nmpc"]["nmpc_converged_share"]:.1%}.' for e in solved]
    return '\n'.join(lines) + '\n'


COMPARISONS = (
    ('planning', 'no planning', "the paper's comparison"),
    ('planning', 'no planning at v_max', 'the plan against the fastest constant speed'),
    ('planning', 'planning without (p7)', 'what the pre-expansion (p7) buys'),
    ('planning', 'planned speed, (a3) off', 'what (a3) buys on top of the planned speed'),
    ('replanning every 0.5 s', 'planning', 'what replanning online buys'),
    ('constant speed, (a3) to rho_d', 'no planning', 'what (a3) buys without a plan'),
)
"""Paired comparisons of the grid report: mode a against mode b on the same seeds, and what the difference means."""
CLAIMS = (('passing_time_s', 'lower', 'passing time [s]'), ('min_distance_m', 'higher', 'min distance [m]'))


CELL_AXES = (
    'scene',
    'n_robots',
    'model',
    'saturation',
    'pose_noise_m',
    'latency_steps',
    'lag_s',
    'compensation',
    'failure',
    'dropout',
)
"""What a row's mode is compared within (a cell): every field of :class:`Point` but the mode and the seed."""


def _cell(row: dict[str, Any]) -> tuple[Any, ...]:
    return tuple(row.get(axis) for axis in CELL_AXES)


def setting_text(row: dict[str, Any]) -> str:
    """A cell's setting in words, scene and N left out: the robot model, the saturation and the faults that are on."""
    words = [f'{row["model"]} model', f'{row["saturation"]} sat']
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


def verdict_summary(rows: list[dict[str, Any]]) -> str:
    """Where each comparison's claim holds: per setting (:func:`setting_text`), in how many cells (scene, N) the
    paired interval says a beats b (+), cannot tell (=) or b beats a (-), for each metric of CLAIMS."""
    table = paired_table(rows)
    settings = list(dict.fromkeys(setting_text(p) for p in table))
    compared = [c for c in COMPARISONS if any((p['a'], p['b']) == c[:2] for p in table)]
    lines = [
        (
            'Cells (scene, N) where a beats b (+), the interval includes zero (=), or b beats a (-); '
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
                plus, same, minus = (found.count(v) for v in ('holds', 'does not hold', 'reversed'))
                counts.append(f'{letter} +{plus} ={same} -{minus}')
            cols.append(', '.join(counts))
        lines.append(f'| {setting} | ' + ' | '.join(cols) + ' |')
    return '\n'.join(lines) + '\n'


def mode_summary(rows: list[dict[str, Any]]) -> str:
    """Per setting and mode, over every scene, N and seed: collision pairs and the runs with any, the runs that did
    not complete, and the range over cells (scene, N) of the share of robot-steps moving backwards (the columns
    whose metrics the rows hold)."""
    columns = [c for c in _MODE_COLUMNS if c[0] in rows[0]]
    lines = [
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


def grid_markdown(rows: list[dict[str, Any]]) -> str:
    """A study's report: where each comparison holds (:func:`verdict_summary`), collisions per mode
    (:func:`mode_summary`), then per cell (scene, N, setting) each mode's means with 95 % bootstrap intervals and
    the paired differences of COMPARISONS with their intervals and verdicts (a claim holds only where the interval
    excludes zero)."""
    lines: list[str] = [verdict_summary(rows), mode_summary(rows)]
    for cell in dict.fromkeys(_cell(r) for r in rows):
        sel = [r for r in rows if _cell(r) == cell]
        modes = list(dict.fromkeys(r['mode'] for r in sel))
        seeds = sorted({r['seed'] for r in sel})
        first = sel[0]
        columns = [c for c in _CELL_COLUMNS if c[0] in first]
        lines += [
            f'### Scene {first["scene"]}, N = {first["n_robots"]}, {setting_text(first)} ({len(seeds)} seeds)',
            '',
            '| mode | ' + ' | '.join(header for _, header, _ in columns) + ' |',
            '|---|' + '---|' * len(columns),
        ]
        for mode in modes:
            cols = [text(cell_values(sel, metric, mode=mode)) for metric, _, text in columns]
            lines.append(f'| {mode} | ' + ' | '.join(cols) + ' |')
        differences = paired_table(sel)
        compared = [c for c in COMPARISONS if any((p['a'], p['b']) == c[:2] for p in differences)]
        if compared:
            lines += [
                '',
                '| comparison (a - b, same seeds) | ' + ' | '.join(t for _, _, t in CLAIMS) + ' |',
                '|---|---|---|',
            ]
        for a, b, meaning in compared:
            found = {p['metric']: p for p in differences if (p['a'], p['b']) == (a, b)}
            cols = [
                f'{found[m]["estimate"].text(3)}: {found[m]["verdict"]}' if m in found else 'n/a' for m, _, _ in CLAIMS
            ]
            lines.append(f'| {a} - {b} ({meaning}) | ' + ' | '.join(cols) + ' |')
        lines.append('')
    return '\n'.join(lines)


def paired_table(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per cell (CELL_AXES), the paired differences of COMPARISONS on each metric of CLAIMS: dicts with the cell's
    fields, a, b, metric, estimate (an :class:`~vtube_planning.stats.Estimate`) and verdict. Comparisons whose
    modes are missing, or whose runs did not all complete, are left out."""
    out = []
    for cell in dict.fromkeys(_cell(r) for r in rows):
        sel = [r for r in rows if _cell(r) == cell]
        fields = dict(zip(CELL_AXES, cell, strict=True))
        for a, b, _ in COMPARISONS:
            for metric, better, _ in CLAIMS:
                if metric not in sel[0]:
                    continue
                diff = _paired(cell_values(sel, metric, mode=a), cell_values(sel, metric, mode=b))
                if diff is not None:
                    out.append(
                        fields | {'a': a, 'b': b, 'metric': metric, 'estimate': diff, 'verdict': verdict(diff, better)}
                    )
    return out


def _interval(values: NDArray[np.float64], digits: int) -> str:
    finite = values[np.isfinite(values)]
    if finite.size < values.size:
        return f'{finite.size} of {values.size} completed'
    return mean_interval(values).text(digits) if values.size > 1 else f'{values[0]:.{digits}f}'


def _paired(a: NDArray[np.float64], b: NDArray[np.float64]) -> Estimate | None:
    if a.size < 2 or a.size != b.size or not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        return None
    return paired_difference(a, b)
