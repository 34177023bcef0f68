"""``vtube replay``: a run as one offline HTML page that plays it (`robotarium_exp.analysis.replay`)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from vtube.cli.arguments import bag_arguments
from vtube.cli.command import EXIT_OK, BadInput, Command, View

if TYPE_CHECKING:
    from robotarium_exp.analysis.replay import Replay


def replay_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        'inputs', type=Path, nargs='+', help='what vtube analyze reads: a .npz log, a testbed folder, bags, ...'
    )
    parser.add_argument('--out', type=Path, required=True, help='the page to write, e.g. run.html')
    parser.add_argument(
        '--scene', default=None, help='the scene the run was recorded in (default: the one its log records)'
    )
    parser.add_argument(
        '--plan', type=Path, default=None, help="a plan file (vtube plan) to show (default: the scene's plan)"
    )
    bag_arguments(parser)


def replay(args: argparse.Namespace) -> Replay:
    from robotarium_exp.analysis.loaders import load_trajectory
    from robotarium_exp.analysis.recorded_tube import check_recorded_tube
    from robotarium_exp.analysis.replay import check_page, flew_a_plan, plan_label, replayed_scene, write_replay
    from robotarium_exp.scene import load_scene
    from vtube.pipeline import plan_for
    from vtube_planning.errors import SceneError

    check_page(args.out)
    bags = {'topic_pattern': args.topic_pattern, 'frame_pattern': args.frame_pattern, 'topics': args.topics}
    trajectory = load_trajectory(list(args.inputs), world_frame=args.world_frame, **bags)
    name = replayed_scene(trajectory, args.scene)
    try:
        scene = load_scene(name)
    except SceneError as err:
        copy = None if args.scene is not None else _scene_copy(name, args.inputs)
        if args.scene is not None:
            raise
        if copy is None:
            why = str(err).rstrip('.')
            msg = (
                f'the run records scene {name!r}, which is not shipped ({why}), and no copy scene_{name}.toml lies '
                'beside it; give its file: --scene PATH.toml.'
            )
            raise BadInput(msg) from err
        scene = load_scene(copy)
    check_recorded_tube(trajectory, scene)
    shown = args.plan is not None or flew_a_plan(trajectory)
    plan = plan_for(scene, plan_file=args.plan) if shown else None
    return write_replay(trajectory, scene, plan, args.out, plan_label(args.plan))


def _scene_copy(name: str, inputs: list[Path]) -> Path | None:
    """The copy of scene ``name`` that vtube writes beside a run's log (``scene_<name>.toml``, in the log's folder
    or in a testbed folder given), or None."""
    for given in inputs:
        copy = (given if given.is_dir() else given.parent) / f'scene_{name}.toml'
        if copy.is_file():
            return copy
    return None


def replay_view(done: Replay) -> View:
    line = (
        f'written {done.out} ({done.size_bytes / 1e3:.0f} kB): {done.robots} robots, {done.duration_s:.2f} s, '
        f'{done.frames} of {done.frames_in_run} frames'
    )
    return View((line,), exit_code=EXIT_OK)


COMMAND = Command('replay', 'a run as one offline HTML page that plays it', replay_arguments, replay, replay_view)
