"""The paper's comparison: the same swarm through scenes A-D with and without planning, over several seeds.

For every scene and seed the swarm flies once with the plan (planned speed, r_a following (a3)) and once without
(constant mid-range speed, constant r_a), from the same jittered initial formation. The paper's claim, checked
per scene on the means over seeds and per seed: with planning the passing time is shorter, the minimum distance
larger, and no two robots collide. With ``baselines``, scenes C and D also fly the paper's baselines (optimized
flocking with v_min = 0 as the paper ran it and a speed-constrained variant; distributed NMPC), compared on safety:
the paper's claim is that the planned method passes more safely (fewer collisions, larger minimum distance).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import replace
from typing import Any

import numpy as np

from vtube_planning.baselines.flocking import FlockingParams, flocking_command
from vtube_planning.baselines.nmpc import NmpcParams, NmpcSwarm
from vtube_planning.geometry.scene import load_scene
from vtube_planning.planning.planner import plan_convex
from vtube_planning.swarm.simulate import SimConfig, simulate

MODES = ('planning', 'no planning')
BASELINE_MODES = ('flocking', 'flocking (v_min)', 'nmpc')
BASELINE_SCENES = ('C', 'D')
COLUMNS = ('passing_time_s', 'min_distance_m', 'collision_pairs', 'tube_violation_steps', 'completed')


def run_study(
    scenes: Iterable[str],
    seeds: Iterable[int],
    *,
    config: SimConfig | None = None,
    progress: Callable[[str], None] | None = None,
    baselines: Iterable[str] = (),
) -> list[dict[str, Any]]:
    """One row per scene, mode and seed with the passage's metrics; ``baselines`` from BASELINE_MODES."""
    config = config or SimConfig()
    rows = []
    for name in scenes:
        scene = load_scene(name)
        plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
        modes = MODES + (tuple(baselines) if scene.name in BASELINE_SCENES else ())
        for seed in seeds:
            for mode in modes:
                law = _baseline_law(mode, scene, config.dt_s) if mode in BASELINE_MODES else None
                result = simulate(
                    scene.tube,
                    scene.swarm,
                    scene.control,
                    plan=plan if mode == 'planning' else None,
                    config=replace(config, seed=seed),
                    baseline=law,
                )
                rows.append(
                    {
                        'scene': scene.name,
                        'mode': mode,
                        'seed': seed,
                        **{k: getattr(result.metrics, k) for k in COLUMNS},
                    }
                )
                if progress is not None:
                    m = result.metrics
                    progress(
                        f'{scene.name} seed {seed} {mode:<11}: passing {m.passing_time_s:.2f} s, '
                        f'min distance {m.min_distance_m:.3f} m, collisions {m.collision_pairs}'
                    )
    return rows


def _baseline_law(mode: str, scene: Any, dt_s: float) -> Callable[..., Any]:
    """The swarm law of a baseline, as the simulator's ``baseline`` hook: (positions, velocities, projection)."""
    if mode == 'nmpc':
        swarm = NmpcSwarm(scene.tube, NmpcParams.for_swarm(scene.swarm))
        return lambda positions, velocities, projection: swarm.command(positions, velocities, projection, dt_s)
    params = FlockingParams.scaled(scene.swarm, speed_constrained=mode == 'flocking (v_min)')
    return lambda positions, velocities, projection: flocking_command(positions, velocities, projection, params)


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


def study_markdown(summary: list[dict[str, Any]], seeds: list[int], config: SimConfig) -> str:
    """The comparison as a Markdown table, with the claim's verdict per scene."""
    model = 'with the acceleration limits (3), (4) per robot' if config.acceleration_limits else "the paper's model"
    lines = [
        (
            f'Scenes with and without planning, Table 1 swarm (N = 20), {model}, dt = {config.dt_s} s, '
            f'seeds {seeds[0]}..{seeds[-1]} (initial jitter {config.jitter_m} m). Means over seeds, [min, max].'
        ),
        '',
        '| scene | mode | passing time [s] | min distance [m] | collisions (pairs) | tube violations (robot-steps) |',
        '|---|---|---|---|---|---|',
    ]
    for entry in summary:
        for mode in entry['modes']:
            e = entry[mode]
            lo, hi = e['passing_time_range_s']
            dlo, dhi = e['min_distance_range_m']
            lines.append(
                f'| {entry["scene"]} | {mode} | {e["passing_time_s"]:.2f} [{lo:.2f}, {hi:.2f}] | '
                f'{e["min_distance_m"]:.3f} [{dlo:.3f}, {dhi:.3f}] | {e["collision_pairs"]} | '
                f'{e["tube_violation_steps"]} |'
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
    return '\n'.join(lines) + '\n'
