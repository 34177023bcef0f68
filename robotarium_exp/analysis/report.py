"""Metrics and reports of a trajectory in a scene: the paper's measures, tracking against a plan, expansion.

Works on any :class:`~robotarium_exp.analysis.trajectory.Trajectory` (testbed files, our logs, motion-capture bags), on
the frames where every robot has a position; dropped frames and reported gaps are part of the result.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.analysis.trajectory import Trajectory
from vtube_planning.geometry.scene import Scene
from vtube_planning.planning.plan import Plan
from vtube_planning.swarm.metrics import passage_metrics, strict_json
from vtube_planning.swarm.step import swarm_density


def along_tube(trajectory: Trajectory, scene: Scene) -> dict[str, np.ndarray]:
    """Per complete frame: time, positions, arc lengths, clearances, speed along the tube, measured density."""
    frames = trajectory.complete_frames()
    t = trajectory.t_s[frames]
    positions = trajectory.positions_m[frames]
    steps, _, n = positions.shape
    projection = scene.tube.project(positions.transpose(1, 0, 2).reshape(2, -1))
    l_m = projection.l_m.reshape(steps, n)
    clearance = projection.clearance_m.reshape(steps, n)
    tangent = projection.tangent.reshape(2, steps, n)
    velocity = np.gradient(positions, t, axis=0) if steps > 1 else np.zeros_like(positions)
    forward = np.einsum('tin,itn->tn', velocity, tangent)
    density = np.array([swarm_density(scene.tube, row, scene.swarm.r_a_m) for row in l_m])
    return {
        't_s': t,
        'positions_m': positions,
        'l_m': l_m,
        'clearance_m': clearance,
        'forward_speed_mps': forward,
        'density_per_m2': density,
        'dropped_frames': int((~frames).sum()),
    }


def narrowing_start(scene: Scene) -> float:
    """Arc length where the tube first gets narrower than at its entrance."""
    grid = np.linspace(0.0, scene.tube.length_m, 4001)
    narrower = np.asarray(scene.tube.half_width(grid)) < float(scene.tube.half_width(0.0)) - 1e-9
    return float(grid[np.argmax(narrower)]) if narrower.any() else scene.tube.length_m


def analyse(
    trajectory: Trajectory, scene: Scene, plan: Plan | None = None, *, collision_distance_m: float | None = None
) -> dict[str, Any]:
    """The measures of :func:`vtube_planning.swarm.metrics.passage_metrics` plus expansion, data quality and
    source, as strict JSON values (no NaN).

    ``collision_distance_m`` overrides the scene's 2 r_p as the distance below which two robots collide.
    """
    data = along_tube(trajectory, scene)
    collision = 2.0 * scene.swarm.r_p_m if collision_distance_m is None else collision_distance_m
    metrics = passage_metrics(
        data['t_s'],
        data['positions_m'],
        data['l_m'],
        data['clearance_m'],
        scene.tube.length_m,
        collision_distance_m=collision,
        forward_speed_mps=data['forward_speed_mps'],
        density_per_m2=data['density_per_m2'],
        plan=plan,
    ).to_json()
    start = narrowing_start(scene)
    extent = np.ptp(data['l_m'], axis=1)
    k = int(np.argmax(data['l_m'].max(axis=1) >= start)) if np.any(data['l_m'].max(axis=1) >= start) else -1
    metrics.update(
        {
            'robots': trajectory.n_robots,
            'frames': int(data['t_s'].size),
            'dropped_frames': data['dropped_frames'],
            'gaps': [{'robot': g.robot, 'start_s': g.start_s, 'end_s': g.end_s} for g in trajectory.gaps],
            'narrowing_start_m': start,
            'extent_start_m': float(extent[0]),
            'extent_at_narrowing_m': float(extent[k]) if k >= 0 else float('nan'),
            'source': trajectory.source,
        }
    )
    return strict_json(metrics)


def write_report(
    out: Path, results: dict[str, tuple[Trajectory, dict[str, Any]]], scene: Scene, plan: Plan | None
) -> Path:
    """metrics.json, report.md and the figures for one or more analysed trajectories (label -> result)."""
    from robotarium_exp.analysis.plots import analysis_figures
    from vtube_planning.plots import save_figure

    out.mkdir(parents=True, exist_ok=True)
    (out / 'metrics.json').write_text(
        json.dumps({k: m for k, (_, m) in results.items()}, indent=1, allow_nan=False), encoding='utf-8'
    )
    figures = {
        name: save_figure(fig, out / f'{name}.png').name for name, fig in analysis_figures(results, scene, plan).items()
    }
    rows = [
        ('passing time [s]', 'passing_time_s', '.2f'),
        ('minimum distance [m]', 'min_distance_m', '.3f'),
        ('collision pairs (< 2 r_p)', 'collision_pairs', 'd'),
        ('tube violations [robot-steps]', 'tube_violation_steps', 'd'),
        ('swarm length at the narrowing [m]', 'extent_at_narrowing_m', '.3f'),
        ('speed tracking, mean [m/s]', 'speed_tracking_mean_mps', '.4f'),
        ('density tracking, mean [1/m^2]', 'density_tracking_mean_per_m2', '.3f'),
        ('frames (dropped)', 'frames', 'd'),
    ]
    labels = list(results)
    lines = [f'# Trajectory analysis: scene {scene.name}', '', f'Plan: {"given" if plan else "none"}. Sources:', '']
    lines += [f'- {label}: {m["source"].get("kind")} `{m["source"].get("path")}`' for label, (_, m) in results.items()]
    lines += ['', '| measure | ' + ' | '.join(labels) + ' |', '|---|' + '---|' * len(labels)]
    for title, key, fmt in rows:
        cells = []
        for label in labels:
            value = results[label][1].get(key)
            cells.append('–' if value is None else format(value, fmt))
        lines.append(f'| {title} | ' + ' | '.join(cells) + ' |')
    for label in labels:
        gaps = results[label][1]['gaps']
        if gaps:
            lines.append(f'\n{label}: {len(gaps)} gap(s) in the data, not interpolated: {gaps[:5]}')
    lines += [''] + [f'![{name}]({file})' for name, file in figures.items()] + ['']
    path = out / 'report.md'
    path.write_text('\n'.join(lines), encoding='utf-8')
    return path
