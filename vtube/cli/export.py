"""``vtube export``: a run's trajectory as a ROS 2 bag (MCAP or sqlite3) for Foxglove and RViz, or as CSV."""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

from vtube.cli.command import EXIT_OK, Command, View


@dataclass(frozen=True)
class Exported:
    """What was written: the file or bag folder, its format, the robots and frames."""

    out: Path
    fmt: str
    robots: int
    frames: int


def export_arguments(parser: argparse.ArgumentParser) -> None:
    from robotarium_exp.analysis.export import FORMATS

    parser.add_argument(
        'inputs', type=Path, nargs='+', help='what vtube analyze reads: a .npz log, a testbed folder, bags, ...'
    )
    parser.add_argument('--format', choices=FORMATS, required=True, dest='fmt', help='mcap or ros2 (a bag), or csv')
    parser.add_argument('--out', type=Path, required=True, help='the bag folder (new) or the .csv file')
    parser.add_argument('--scene', default=None, help='the scene whose tube (and obstacles) the bag shows as markers')


def export(args: argparse.Namespace) -> Exported:
    from robotarium_exp.analysis.export import export as write
    from robotarium_exp.analysis.loaders import load_trajectory
    from robotarium_exp.scene import load_scene

    trajectory = load_trajectory(list(args.inputs))
    scene = load_scene(args.scene) if args.scene is not None else None
    out = write(trajectory, args.out, args.fmt, scene)
    return Exported(out, args.fmt, trajectory.n_robots, trajectory.t_s.size)


def export_view(done: Exported) -> View:
    line = f'written {done.out} ({done.fmt}): {done.robots} robots, {done.frames} frames'
    return View((line,), exit_code=EXIT_OK)


COMMAND = Command('export', 'a trajectory as a ROS 2 bag (MCAP, sqlite3) or CSV', export_arguments, export, export_view)
