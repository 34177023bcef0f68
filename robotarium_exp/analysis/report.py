"""Metrics and reports of a trajectory, with or without a tube: distances, coverage, the passage, tracking.

Works on any [`Trajectory`][robotarium_exp.analysis.trajectory.Trajectory] (testbed files, our logs, motion-capture
bags). Without a scene the result holds the measures that need no tube: robots, frames, each robot's coverage, gaps,
pairwise distances and collisions. With a scene it adds the passage (`passage`: timed from the start a flight
of ours recorded, as ``vtube robotarium run`` times it, with the tube violations of the Robotarium robot's body;
otherwise a passing time only for a passage observed whole, and violations of the centres), tube violations over
each robot's own coverage, the expansion before the narrowing and,
with a plan, the tracking errors (on the frames where every robot has a position). The result
([`RecordingMetrics`][robotarium_exp.analysis.metrics.RecordingMetrics]) records what was read (paths, sizes, hashes),
the options and the package version.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import tempfile
from collections.abc import Mapping
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.analysis.distances import PairDistances, pair_distances
from robotarium_exp.analysis.loaders import input_record
from robotarium_exp.analysis.metrics import Analysis, PairMeasure, RecordingMetrics, TrackingErrors, TubeMetrics
from robotarium_exp.analysis.passage import AlongTube, FlightStart, along_tube, observed_passage, recorded_passage
from robotarium_exp.analysis.trajectory import PLAUSIBLE_M, Trajectory
from robotarium_exp.spec import ROBOTARIUM
from robotarium_exp.tracking import narrowing_start
from vtube_planning import __version__
from vtube_planning.files import write_atomically
from vtube_planning.geometry.scene import Scene
from vtube_planning.planning.plan import Plan
from vtube_planning.provenance import provenance
from vtube_planning.swarm.map_contact import map_contact
from vtube_planning.swarm.metrics import tracking_errors, tube_violations

FloatArray = NDArray[np.float64]


def analyse(
    trajectory: Trajectory,
    scene: Scene | None = None,
    plan: Plan | None = None,
    *,
    collision_distance_m: float | None = None,
    options: Mapping[str, Any] | None = None,
) -> Analysis:
    """Measure ``trajectory`` (module docstring).

    ``collision_distance_m`` is the distance below which two robots collide: by default the scene's 2 r_p; without
    a scene and without it, collisions are not counted (None).
    """
    collision = collision_distance_m if collision_distance_m is not None or scene is None else 2.0 * scene.swarm.r_p_m
    distances = pair_distances(trajectory.positions_m, collision)
    pairs = _pair_measures(trajectory, distances, collision)
    measured = np.isfinite(distances.min_m)
    closest = pairs[int(np.argmin(np.where(measured, distances.min_m, np.inf)))] if measured.any() else None
    along = along_tube(trajectory, scene) if scene is not None else None
    metrics = RecordingMetrics(
        robot_ids=trajectory.robot_ids,
        frames=int(trajectory.t_s.size),
        complete_frames=int(trajectory.complete_frames().sum()),
        coverage=trajectory.coverage,
        gaps=trajectory.gaps,
        pairs=pairs,
        closest=closest,
        collision_distance_m=collision,
        collision_frames=distances.frames_below if collision is not None else None,
        tube=_tube_metrics(trajectory, scene, plan, along, distances)
        if scene is not None and along is not None
        else None,
        source=trajectory.source,
        inputs=input_record(trajectory.source.get('files', [])),
        options=options or {},
        scene=scene.name if scene is not None else None,
        planned=plan is not None,
        vtube_version=__version__,
        provenance=provenance(scene=scene),
    )
    return Analysis(trajectory, distances, along, metrics)


def _pair_measures(
    trajectory: Trajectory, distances: PairDistances, collision: float | None
) -> tuple[PairMeasure, ...]:
    """Every pair's closest approach over its common frames, and its frames closer than ``collision``."""
    ids, t = trajectory.robot_ids, trajectory.t_s
    return tuple(
        PairMeasure(
            robots=(ids[i], ids[j]),
            common_frames=int(n),
            min_distance_m=float(d) if np.isfinite(d) else None,
            time_s=float(t[k]) if k >= 0 else None,
            frames_closer=int(below) if collision is not None else None,
        )
        for i, j, n, d, k, below in zip(
            distances.first,
            distances.second,
            distances.common_frames,
            distances.min_m,
            distances.min_frame,
            distances.below,
            strict=True,
        )
    )


def _obstacle_clearance(trajectory: Trajectory, scene: Scene, body_radius: float) -> tuple[float | None, ...] | None:
    """Per robot, the smallest distance of its body to the scene's obstacles over the frames it was seen."""
    if not scene.obstacles:
        return None
    out: list[float | None] = []
    for k in range(len(trajectory.robot_ids)):
        points = trajectory.positions_m[:, :, k]
        seen = points[np.all(np.isfinite(points), axis=1)]
        gap = float(scene.obstacles.clearance(seen).min()) - body_radius if seen.size else None
        out.append(None if gap is None else max(gap, 0.0))
    return tuple(out)


def _tube_metrics(
    trajectory: Trajectory, scene: Scene, plan: Plan | None, along: AlongTube, distances: PairDistances
) -> TubeMetrics:
    """The passage, tube violations, the swarm's length before the narrowing, the tracking of ``plan`` and the
    closest two robots came in the passage and after it."""
    length = scene.tube.length_m
    start = FlightStart.from_record(trajectory.source.get('flight_start'), str(trajectory.source.get('path')))
    if start is None:
        passage, body_radius = observed_passage(along, length, trajectory.robot_ids), 0.0
    else:  # a flight of ours: on a Robotarium its robots' bodies, as the experiment counts them; simulated, points
        passage = recorded_passage(along, length, trajectory.robot_ids, start)
        body_radius = 0.0 if trajectory.source.get('point_robots') else 0.5 * ROBOTARIUM.robot_diameter_m
    violation_steps, robots_outside, max_outside = tube_violations(along.l_m, along.clearance_m, length, body_radius)
    complete = along.complete
    narrowing = narrowing_start(scene)
    l_c = along.l_m[complete]
    extent_start = extent_at_narrowing = None
    tracking = None
    if l_c.size:
        extent = np.ptp(l_c, axis=1)
        reached = np.flatnonzero(l_c.max(axis=1) >= narrowing)
        extent_start = float(extent[0])
        extent_at_narrowing = float(extent[reached[0]]) if reached.size else None
        if plan is not None:
            speed, density = along.forward_speed_mps[complete], along.density_per_m2[complete]
            errors = tracking_errors(l_c, speed, density, plan, length)
            tracking = TrackingErrors(**errors) if errors else None
    return TubeMetrics(
        obstacle_clearance_m=_obstacle_clearance(trajectory, scene, body_radius),
        passage=passage,
        tube_violation_steps=violation_steps,
        robots_outside=robots_outside,
        max_outside_m=max_outside,
        body_radius_m=body_radius,
        narrowing_start_m=narrowing,
        extent_start_m=extent_start,
        extent_at_narrowing_m=extent_at_narrowing,
        tracking=tracking,
        closest_in_passage=_closest(trajectory.t_s, distances.frame_min_m, passage.last_exit_s, before=True),
        closest_after_passage=_closest(trajectory.t_s, distances.frame_min_m, passage.last_exit_s, before=False),
        map_contact=(
            map_contact(
                along.t_s,
                trajectory.positions_m,
                scene,
                body_radius,
                along.l_m,
                parks=not trajectory.source.get('point_robots'),  # a simulation's robots drive on, a flight's park
            )
            if scene.obstacles or scene.workspace is not None
            else None
        ),
    )


def _closest(
    t_s: FloatArray, frame_min_m: FloatArray, last_exit_s: float | None, *, before: bool
) -> tuple[float, float] | None:
    """The smallest of ``frame_min_m`` and its time over the frames up to ``last_exit_s`` (``before``) or after it;
    None without a last exit or a measured frame there."""
    if last_exit_s is None:
        return None
    where = (t_s <= last_exit_s) if before else (t_s > last_exit_s)
    values = np.where(where & np.isfinite(frame_min_m), frame_min_m, np.inf)
    if not np.isfinite(values).any():
        return None
    k = int(np.argmin(values))
    return float(values[k]), float(t_s[k])


ROW_TITLES = (
    'robots',
    'frames (every robot present)',
    'minimum distance [m]',
    'minimum distance up to the last exit (passage) [m]',
    'minimum distance after the last exit (parking) [m]',
    'collision distance [m]',
    'collision pairs',
    'passing time [s]',
    'tube violations [robot-frames]',
    'swarm length at the narrowing [m]',
    'speed tracking, mean [m/s]',
    'density tracking, mean [1/m^2]',
)
"""The rows of the report's table, one column per analysed trajectory (`_cells`)."""


def write_report(out: Path, results: dict[str, Analysis], scene: Scene | None, plan: Plan | None) -> Path:
    """metrics.json, report.md and the figures for one or more analysed trajectories (label -> analysis), made in a
    hidden folder beside ``out`` and moved into it only when all are written: a run killed while it draws leaves
    ``out`` as it was, never one run's metrics beside another's report."""
    out.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f'.{out.name}.', suffix='.partial', dir=out.parent))
    try:
        _write_report(staging, results, scene, plan)
        for name in ('metrics.json', *(f.name for f in staging.iterdir() if f.suffix == '.png'), 'report.md'):
            os.replace(staging / name, out / name)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return out / 'report.md'


def _write_report(out: Path, results: dict[str, Analysis], scene: Scene | None, plan: Plan | None) -> None:
    """`write_report`'s files, into the folder ``out``."""
    from robotarium_exp.analysis.plots import analysis_figures
    from vtube_planning.plots import save_figure

    write_atomically(
        out / 'metrics.json',
        json.dumps({k: a.metrics.to_json() for k, a in results.items()}, indent=1, allow_nan=False),
    )
    figures = {
        name: save_figure(fig, out / f'{name}.png').name for name, fig in analysis_figures(results, scene, plan).items()
    }
    labels = list(results)
    lines = _header(results, scene, plan)
    lines += ['', '| measure | ' + ' | '.join(labels) + ' |', '|---|' + '---|' * len(labels)]
    columns = [_cells(a.metrics) for a in results.values()]
    lines += [f'| {title} | ' + ' | '.join(c[k] for c in columns) + ' |' for k, title in enumerate(ROW_TITLES)]
    for label, analysis in results.items():
        lines += _notes(label, analysis.metrics)
    lines += [''] + [f'![{name}]({file})' for name, file in figures.items()] + ['']
    write_atomically(out / 'report.md', '\n'.join(lines))


def _header(results: dict[str, Analysis], scene: Scene | None, plan: Plan | None) -> list[str]:
    """Title, provenance, plan and sources."""
    title = f'scene {scene.name}' if scene is not None else 'no tube (no scene given)'
    first = next(iter(results.values())).metrics
    made = first.provenance
    made_from = f'; scene file {made["scene_source"]} (sha256 {made["scene_sha256"][:16]})' if scene else ''
    plan_file = first.options.get('plan')
    plan_text = 'none' if plan is None else f'`{plan_file}`' if plan_file else 'given'
    lines = [
        f'# Trajectory analysis: {title}',
        '',
        f'Made by vtube {made["vtube_version"]} on {made["utc"]} (UTC) with `{made["command"]}`{made_from}.',
        '',
        f'Plan: {plan_text}. Sources:',
        '',
    ]
    return lines + [
        f'- {label}: {a.metrics.source.get("kind")} `{a.metrics.source.get("path")}`' for label, a in results.items()
    ]


def _cells(m: RecordingMetrics) -> list[str]:
    """One column of the report's table (`ROW_TITLES`)."""
    tube = m.tube
    tracking = tube.tracking if tube is not None else None
    closest = m.closest
    distance = _number(closest.min_distance_m if closest else None, '.3f')
    if closest is not None and closest.min_distance_m is not None:
        distance += f' ({" - ".join(closest.robots)}, t = {closest.time_s:.2f} s)'
    return [
        _number(m.robots, 'd'),
        f'{_number(m.frames, "d")} ({m.complete_frames})',
        distance,
        _at(tube.closest_in_passage if tube else None),
        _at(tube.closest_after_passage if tube else None),
        _number(m.collision_distance_m, '.3f'),
        _number(m.collision_pairs, 'd'),
        _number(tube.passage.passing_time_s if tube else None, '.2f'),
        _number(tube.tube_violation_steps if tube else None, 'd'),
        _number(tube.extent_at_narrowing_m if tube else None, '.3f'),
        _number(tracking.speed_tracking_mean_mps if tracking else None, '.4f'),
        _number(tracking.density_tracking_mean_per_m2 if tracking else None, '.3f'),
    ]


def _at(closest: tuple[float, float] | None) -> str:
    """A distance and its time, or '–'."""
    return '–' if closest is None else f'{closest[0]:.3f} (t = {closest[1]:.2f} s)'


def _number(value: float | None, fmt: str) -> str:
    """``value`` formatted; '–' when it is missing or not finite (None in metrics.json)."""
    return '–' if value is None or not math.isfinite(value) else format(value, fmt)


def _notes(label: str, m: RecordingMetrics) -> list[str]:
    """Coverage, gaps, what was ignored and what of the passage was not observed, in words."""
    lines = [
        '',
        f'## {label}',
        '',
        '| robot | samples | first [s] | last [s] | frames | missing: before, after, gaps |',
        '|---|---|---|---|---|---|',
    ]
    lines += [
        f'| {c.robot} | {c.samples} | {_number(c.first_s, ".2f")} | {_number(c.last_s, ".2f")} | {c.frames} | '
        f'{c.before_first}, {c.after_last}, {c.in_gaps} |'
        for c in m.coverage
    ]
    repeated, non_finite = sum(c.repeated_stamps for c in m.coverage), sum(c.non_finite for c in m.coverage)
    if repeated or non_finite:
        lines.append(
            f'\nSamples left out: {repeated} at a repeated stamp, {non_finite} with a NaN, infinite or implausible (beyond {PLAUSIBLE_M:g} m) position.'
        )
    if m.gaps:
        lines.append(f'\n{len(m.gaps)} gap(s), never interpolated across: {[asdict(g) for g in m.gaps[:5]]}')
    if m.source.get('cut'):
        lines.append('\nCut in a save: ' + '; '.join(m.source['cut']) + '.')
    ignored = m.source.get('ignored') or []
    if ignored:
        lines.append(
            f'\nIgnored ({len(ignored)}): ' + '; '.join(' '.join(str(v) for v in i.values()) for i in ignored[:20])
        )
    if m.tube is not None:
        lines.append(f'\nPassage: {m.tube.passage.start}; tube violations of {m.tube.violations_counted()}.')
    if m.tube is not None and m.tube.passage.unobserved:
        unobserved = '; '.join(m.tube.passage.unobserved)
        lines.append(f'\nNo passing time: the passage was not observed whole: {unobserved}.')
    return lines
