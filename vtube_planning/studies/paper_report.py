"""The paper's comparison per scene (``vtube study``): means and ranges per mode, and whether its claims hold.

With planning the passing time is shorter, the minimum distance larger, and no two robots collide; against the
baselines, planning passes more safely. `summarise` checks this per scene on the means over seeds and per
seed; `study_markdown` writes it. Rows are those of `run_point` with their
`Point`'s fields; the grid's reports are in `vtube_planning.studies.study_report`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from vtube_planning.studies.seeds import seeds_text
from vtube_planning.studies.study import BASELINE_MODES, RunSettings


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
            f'seeds {seeds_text(seeds)} (initial jitter {settings.jitter_m} m). Means over seeds, [min, max].'
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
