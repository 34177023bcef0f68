"""``vtube analyze``: metrics, figures and a report of returned or recorded data (`vtube.pipeline.analyse_data`)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from vtube.cli.arguments import bag_arguments, positive, writable_folder
from vtube.cli.command import EXIT_FAILED, EXIT_OK, BadInput, Command, View

if TYPE_CHECKING:
    from vtube.pipeline import Analysed


def analyze_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        'inputs',
        type=Path,
        nargs='+',
        help='a folder of vtube_*.npy, a .npz log, a .mat file, .bag files, a ROS2 bag folder or .mcap/.db3 files',
    )
    parser.add_argument('--scene', default=None, help='the scene the data was recorded in (omit: no tube metrics)')
    parser.add_argument('--out', type=Path, required=True, help='folder for metrics.json, report.md and figures')
    parser.add_argument('--plan', type=Path, default=None, help='a plan file (vtube plan) to track against')
    parser.add_argument('--compare', type=Path, default=None, help='a simulation log to show side by side')
    bag_arguments(parser)
    parser.add_argument(
        '--max-gap',
        default=None,
        help="longest hole in a robot's samples that is interpolated, e.g. 3periods (default), 0.25s, 250ms",
    )
    parser.add_argument(
        '--collision-distance',
        type=positive,
        default=None,
        dest='collision_distance_m',
        help="centre distance counted as a collision (default: the scene's 2 r_p; none without a scene)",
    )


def analyze(args: argparse.Namespace) -> Analysed:
    from vtube.pipeline import AnalysisOptions, analyse_data

    writable_folder(args.out)
    if args.plan is not None and args.scene is None:
        raise BadInput('--plan needs the scene it was made for (--scene).')
    options = AnalysisOptions(
        scene=args.scene,
        plan_file=args.plan,
        compare=args.compare,
        topic_pattern=args.topic_pattern,
        frame_pattern=args.frame_pattern,
        topics=tuple(args.topics) if args.topics is not None else None,
        world_frame=args.world_frame,
        max_gap=args.max_gap,
        collision_distance_m=args.collision_distance_m,
    )
    return analyse_data(args.inputs, args.out, options)


def analyze_view(analysed: Analysed) -> View:
    trajectory, m, scene = analysed.data.trajectory, analysed.data.metrics, analysed.scene
    source = trajectory.source
    where = f'in scene {scene.name}' if scene is not None else 'without a tube'
    lines = [
        (
            f'analysis of {source.get("kind")} {source.get("path")} {where}: {trajectory.n_robots} robots, '
            f'{m.frames} frames ({m.complete_frames} with every robot), {len(m.gaps)} gaps, '
            f'{len(source.get("ignored") or [])} topics/frames/variables ignored'
        )
    ]
    lines += [f'  {cut}' for cut in source.get('cut') or ()]  # a file the testbed stopped writing mid-save
    if m.closest is not None:
        pair = ' and '.join(m.closest.robots)
        closest = f'minimum distance {m.closest.min_distance_m:.3f} m ({pair}, t = {m.closest.time_s:.2f} s)'
    else:
        closest = 'one robot: no distances' if trajectory.n_robots < 2 else 'no two robots seen at the same time'
    collisions = (
        f'{m.collision_pairs} pairs closer than {m.collision_distance_m:.3f} m'
        if m.collision_distance_m is not None
        else 'collisions not counted (give --collision-distance)'
    )
    lines.append(f'  {closest}, {collisions}')
    if m.tube is not None and m.tube.closest_in_passage is not None:
        apart = [('up to the last exit (passage)', m.tube.closest_in_passage)]
        apart += [('after it (parking)', m.tube.closest_after_passage)] if m.tube.closest_after_passage else []
        lines.append('  minimum distance ' + ', '.join(f'{when} {d:.3f} m (t = {t:.2f} s)' for when, (d, t) in apart))
    if m.tube is not None:
        passage = m.tube.passage
        if passage.passing_time_s is None:
            lines.append(f'  no passing time: {"; ".join(passage.unobserved)} ({passage.start})')
        else:
            lines.append(f'  passing time {passage.passing_time_s:.2f} s ({passage.start})')
        lines.append(f'  {m.tube.tube_violation_steps} tube violations (robot-frames, {m.tube.violations_counted()})')
        clearances = m.tube.obstacle_clearance_m
        if clearances is not None:
            seen = [(c, r) for c, r in zip(clearances, m.robot_ids, strict=True) if c is not None]
            closest = f'{min(seen)[0]:.3f} m ({min(seen)[1]})' if seen else 'no robot seen'
            lines.append(f'  closest approach to an obstacle {closest}, {m.tube.violations_counted()}')
    failures = m.failures()
    if failures:
        lines.append(f'  FAILED: {"; ".join(failures)}')
    lines.append(f'  written {analysed.report}, {analysed.metrics_file}')
    # the JSON object: what metrics.json holds under "data"
    return View(tuple(lines), m.to_json(), exit_code=EXIT_FAILED if failures else EXIT_OK)


COMMAND = Command(
    'analyze',
    'metrics, figures and a report of returned or recorded data',
    analyze_arguments,
    analyze,
    analyze_view,
    json=True,
)
