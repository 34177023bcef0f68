"""Metrics and reports of a trajectory, with or without a tube: distances, coverage, the passage, tracking.

Works on any :class:`~robotarium_exp.analysis.trajectory.Trajectory` (testbed files, our logs, motion-capture bags).
Without a scene the result holds the measures that need no tube: robots, frames, each robot's coverage, gaps,
pairwise distances and collisions. With a scene it adds the passage (:mod:`.passage`: a passing time only for a
passage observed whole), tube violations over each robot's own coverage, the expansion before the narrowing and,
with a plan, the tracking errors (on the frames where every robot has a position). The result records what was
read (paths, sizes, hashes), the options and the package version, and is strict JSON (None for what is missing).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.analysis.distances import PairDistances, pair_distances
from robotarium_exp.analysis.loaders import input_record
from robotarium_exp.analysis.passage import AlongTube, along_tube, observed_passage
from robotarium_exp.analysis.trajectory import Trajectory
from robotarium_exp.tracking import narrowing_start
from vtube_planning import __version__
from vtube_planning.geometry.scene import Scene
from vtube_planning.planning.plan import Plan
from vtube_planning.provenance import provenance
from vtube_planning.swarm.metrics import strict_json, tracking_errors, tube_violations


@dataclass(frozen=True)
class Analysis:
    """A trajectory, its distances, what the tube says of it (None without a scene), and the metrics (JSON)."""

    trajectory: Trajectory
    distances: PairDistances
    along: AlongTube | None
    metrics: dict[str, Any]


def analyse(
    trajectory: Trajectory,
    scene: Scene | None = None,
    plan: Plan | None = None,
    *,
    collision_distance_m: float | None = None,
    options: dict[str, Any] | None = None,
) -> Analysis:
    """Measure ``trajectory`` (module docstring).

    ``collision_distance_m`` is the distance below which two robots collide: by default the scene's 2 r_p; without
    a scene and without it, collisions are not counted (None).
    """
    ids = trajectory.robot_ids
    collision = collision_distance_m if collision_distance_m is not None or scene is None else 2.0 * scene.swarm.r_p_m
    distances = pair_distances(trajectory.positions_m, collision)
    t = trajectory.t_s
    pairs = [
        {
            'robots': [ids[i], ids[j]],
            'common_frames': int(n),
            'min_distance_m': float(d),
            'time_s': float(t[k]) if k >= 0 else None,
            'frames_closer': int(below) if collision is not None else None,
        }
        for i, j, n, d, k, below in zip(
            distances.first,
            distances.second,
            distances.common_frames,
            distances.min_m,
            distances.min_frame,
            distances.below,
            strict=True,
        )
    ]
    measured = np.isfinite(distances.min_m)
    closest = pairs[int(np.argmin(np.where(measured, distances.min_m, np.inf)))] if measured.any() else None
    colliding = [p['robots'] for p in pairs if collision is not None and p['frames_closer']]
    complete = trajectory.complete_frames()
    metrics: dict[str, Any] = {
        'robots': trajectory.n_robots,
        'robot_ids': list(ids),
        'frames': int(t.size),
        'complete_frames': int(complete.sum()),
        'coverage': [asdict(c) for c in trajectory.coverage],
        'gaps': [asdict(g) for g in trajectory.gaps],
        'min_distance_m': closest['min_distance_m'] if closest else None,
        'min_distance_pair': closest['robots'] if closest else None,
        'min_distance_time_s': closest['time_s'] if closest else None,
        'pairs_without_common_frames': [p['robots'] for p in pairs if not p['common_frames']],
        'collision_distance_m': collision,
        'collision_pairs': len(colliding) if collision is not None else None,
        'colliding_pairs': colliding if collision is not None else None,
        'collision_frames': distances.frames_below if collision is not None else None,
        'pairs': pairs,
    }
    along = along_tube(trajectory, scene) if scene is not None else None
    if scene is not None and along is not None:
        metrics.update(_tube_metrics(trajectory, scene, plan, along))
    metrics.update(
        {
            'source': trajectory.source,
            'inputs': input_record(trajectory.source.get('files', [])),
            'options': options or {},
            'scene': scene.name if scene is not None else None,
            'plan': plan is not None,
            'vtube_version': __version__,
            'provenance': provenance(scene=scene),
        }
    )
    return Analysis(trajectory, distances, along, strict_json(metrics))


def _tube_metrics(trajectory: Trajectory, scene: Scene, plan: Plan | None, along: AlongTube) -> dict[str, Any]:
    """The passage, tube violations, expansion and tracking."""
    length = scene.tube.length_m
    passage = observed_passage(along, length, trajectory.robot_ids)
    violation_steps, robots_outside, max_outside = tube_violations(along.l_m, along.clearance_m, length)
    out: dict[str, Any] = {
        'passing_time_s': passage.passing_time_s,
        'completed': passage.passing_time_s is not None,
        'passage': asdict(passage),
        'first_entry_s': passage.first_entry_s,
        'last_exit_s': passage.last_exit_s,
        'robots_passed': passage.robots_passed,
        'tube_violation_steps': violation_steps,
        'robots_outside': robots_outside,
        'max_outside_m': max_outside,
    }
    complete = along.complete
    start = narrowing_start(scene)
    out['narrowing_start_m'] = start
    l_c = along.l_m[complete]
    if l_c.size:
        extent = np.ptp(l_c, axis=1)
        reached = np.flatnonzero(l_c.max(axis=1) >= start)
        out['extent_start_m'] = float(extent[0])
        out['extent_at_narrowing_m'] = float(extent[reached[0]]) if reached.size else None
    else:
        out['extent_start_m'] = out['extent_at_narrowing_m'] = None
    if plan is not None and l_c.size:
        out.update(
            tracking_errors(
                l_c, along.forward_speed_mps[complete], along.density_per_m2[complete], plan, scene.tube.length_m
            )
        )
    return out


def write_report(out: Path, results: dict[str, Analysis], scene: Scene | None, plan: Plan | None) -> Path:
    """metrics.json, report.md and the figures for one or more analysed trajectories (label -> analysis)."""
    from robotarium_exp.analysis.plots import analysis_figures
    from vtube_planning.plots import save_figure

    out.mkdir(parents=True, exist_ok=True)
    (out / 'metrics.json').write_text(
        json.dumps({k: a.metrics for k, a in results.items()}, indent=1, allow_nan=False), encoding='utf-8'
    )
    figures = {
        name: save_figure(fig, out / f'{name}.png').name for name, fig in analysis_figures(results, scene, plan).items()
    }
    rows = [
        ('robots', 'robots', 'd'),
        ('frames (every robot present)', 'frames', 'd'),
        ('minimum distance [m]', 'min_distance_m', '.3f'),
        ('collision distance [m]', 'collision_distance_m', '.3f'),
        ('collision pairs', 'collision_pairs', 'd'),
        ('passing time [s]', 'passing_time_s', '.2f'),
        ('tube violations [robot-frames]', 'tube_violation_steps', 'd'),
        ('swarm length at the narrowing [m]', 'extent_at_narrowing_m', '.3f'),
        ('speed tracking, mean [m/s]', 'speed_tracking_mean_mps', '.4f'),
        ('density tracking, mean [1/m^2]', 'density_tracking_mean_per_m2', '.3f'),
    ]
    labels = list(results)
    title = f'scene {scene.name}' if scene is not None else 'no tube (no scene given)'
    first = next(iter(results.values())).metrics
    made = first['provenance']
    made_from = f'; scene file {made["scene_source"]} (sha256 {made["scene_sha256"][:16]})' if scene else ''
    plan_file = first['options'].get('plan')
    plan_text = 'none' if plan is None else f'`{plan_file}`' if plan_file else 'given'
    lines = [
        f'# Trajectory analysis: {title}',
        '',
        f'Made by vtube {made["vtube_version"]} on {made["utc"]} (UTC) with `{made["command"]}`{made_from}.',
        '',
        f'Plan: {plan_text}. Sources:',
        '',
    ]
    lines += [
        f'- {label}: {a.metrics["source"].get("kind")} `{a.metrics["source"].get("path")}`'
        for label, a in results.items()
    ]
    lines += ['', '| measure | ' + ' | '.join(labels) + ' |', '|---|' + '---|' * len(labels)]
    for name, key, fmt in rows:
        cells = []
        for label in labels:
            m = results[label].metrics
            value = m.get(key)
            cell = '–' if value is None else format(value, fmt)
            if key == 'frames':
                cell += f' ({m["complete_frames"]})'
            if key == 'min_distance_m' and value is not None:
                cell += f' ({" - ".join(m["min_distance_pair"])}, t = {m["min_distance_time_s"]:.2f} s)'
            cells.append(cell)
        lines.append(f'| {name} | ' + ' | '.join(cells) + ' |')
    for label, analysis in results.items():
        lines += _notes(label, analysis.metrics)
    lines += [''] + [f'![{name}]({file})' for name, file in figures.items()] + ['']
    path = out / 'report.md'
    path.write_text('\n'.join(lines), encoding='utf-8')
    return path


def _notes(label: str, m: dict[str, Any]) -> list[str]:
    """Coverage, gaps, what was ignored and what of the passage was not observed, in words."""
    lines = [
        '',
        f'## {label}',
        '',
        '| robot | samples | first [s] | last [s] | frames | missing: before, after, gaps |',
    ]
    lines.append('|---|---|---|---|---|---|')
    for c in m['coverage']:
        first = '–' if c['first_s'] is None else f'{c["first_s"]:.2f}'
        last = '–' if c['last_s'] is None else f'{c["last_s"]:.2f}'
        lines.append(
            f'| {c["robot"]} | {c["samples"]} | {first} | {last} | {c["frames"]} | '
            f'{c["before_first"]}, {c["after_last"]}, {c["in_gaps"]} |'
        )
    left_out = {k: sum(c[k] for c in m['coverage']) for k in ('repeated_stamps', 'non_finite')}
    if any(left_out.values()):
        lines.append(
            f'\nSamples left out: {left_out["repeated_stamps"]} at a repeated stamp, '
            f'{left_out["non_finite"]} with a NaN or infinite position.'
        )
    if m['gaps']:
        lines.append(f'\n{len(m["gaps"])} gap(s), never interpolated across: {m["gaps"][:5]}')
    ignored = m['source'].get('ignored') or []
    if ignored:
        lines.append(
            f'\nIgnored ({len(ignored)}): ' + '; '.join(' '.join(str(v) for v in i.values()) for i in ignored[:20])
        )
    passage = m.get('passage')
    if passage and passage['unobserved']:
        lines.append('\nNo passing time: the passage was not observed whole: ' + '; '.join(passage['unobserved']) + '.')
    return lines
