"""``vtube tube generate``: a regular tube generated from an obstacle map, written as an ordinary scene file;
``vtube tube example``: a shipped Robotarium map file (package data, ``vtube/maps/*.toml``), to start from."""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING

from vtube.cli.command import BadInput, Command, View
from vtube_planning.files import write_atomically

if TYPE_CHECKING:
    from vtube_planning.geometry.from_maps.generate import GeneratedTube


@dataclass(frozen=True)
class TubeGenerated:
    """The scene file written from ``source``, and the tube generated."""

    source: Path
    path: Path
    generated: GeneratedTube
    seconds: float


def generate_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        'map', type=Path, help='a map file: a scene file with [tube.generate], [workspace], [obstacles]'
    )
    parser.add_argument('--out', type=Path, required=True, help='the scene file to write (must not exist)')


def generate(args: argparse.Namespace) -> TubeGenerated:
    import time

    from vtube_planning.geometry.from_maps.map_file import generated_scene

    path: Path = args.out
    if path.exists():
        msg = f'{path} exists; give another file name (nothing was written).'
        raise BadInput(msg)
    started = time.perf_counter()
    text, generated = generated_scene(args.map.read_text(encoding='utf-8'), str(args.map), path.parent)
    seconds = time.perf_counter() - started
    _require_room_at_the_ends(text, path, str(args.map))
    path.parent.mkdir(parents=True, exist_ok=True)
    write_atomically(path, text)
    return TubeGenerated(args.map, path, generated, seconds)


def _require_room_at_the_ends(text: str, path: Path, map_file: str) -> None:
    """Refuse a generated scene (``text``, to be written to ``path``) whose swarm would start on an obstacle or off
    the map, or run out beyond the goal into one (`vtube.starts.require_room_to_start`, `require_room_beyond_goal`):
    the generator checks the ends as well as the tube."""
    from robotarium_exp.scene import TABLE, robotarium_scene
    from vtube.starts import require_room_beyond_goal, require_room_to_start
    from vtube_planning.geometry.scene import scene_data, scene_from_data

    data = scene_data(text, str(path))
    build = robotarium_scene if TABLE in data else scene_from_data
    scene = build(data, name=Path(map_file).stem, source=str(path))
    require_room_to_start(scene, map_file)
    require_room_beyond_goal(scene, map_file)


def generate_view(result: TubeGenerated) -> View:
    summary, certificate = result.generated.tube.summary(), result.generated.certificate
    return View(
        (
            f'tube generated from {result.source} in {result.seconds:.2f} s, written to {result.path}',
            f'  length                {summary["length_m"]:.3f} m, {len(result.generated.path_m)} path vertices',
            f'  half-width            {summary["half_width_min_m"]:.3f} .. {summary["half_width_max_m"]:.3f} m',
            f'  min curvature radius  {summary["curvature_radius_min_m"]:.3f} m',
            f'  max lambda |kappa|    {summary["lambda_kappa_max"]:.3f}  (regular below 1)',
            f'  obstacles             clear: closest {certificate}',
            *(
                [f'  ends                  held straight along the headings for lead_m = {result.generated.lead_m:g} m']
                if result.generated.lead_m
                else []
            ),
            *_unknown_lines(result.generated),
        )
    )


def _unknown_lines(generated: GeneratedTube) -> list[str]:
    """What the map's images made of their unknown cells (nothing for a map without images)."""
    images = generated.obstacles.images
    if not images:
        return []
    share = generated.obstacles.unknown_share(generated.tube)
    if share is None:
        return [
            '  unknown cells         occupied (never mapped is never free; unknown = "free" in an image allows them)'
        ]
    return [
        f'  unknown cells         FREE (unknown = "free"): {100 * share:.1f} % of the tube lies on cells never mapped'
    ]


def map_examples() -> dict[str, str]:
    """The shipped Robotarium map files, name -> text (the layouts of docs/maps, each checked to fit the testbed)."""
    folder = resources.files('vtube') / 'maps'
    return {
        entry.name.removesuffix('.toml'): entry.read_text(encoding='utf-8')
        for entry in sorted(folder.iterdir(), key=lambda entry: entry.name)
        if entry.name.endswith('.toml')
    }


@dataclass(frozen=True)
class MapWritten:
    """A shipped map ``name`` written to ``path``."""

    name: str
    path: Path


def example_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('name', choices=sorted(map_examples()), help='the shipped map')
    parser.add_argument('file', type=Path, help='the .toml file to write (must not exist)')


def example(args: argparse.Namespace) -> MapWritten:
    from vtube.cli.example import write_new

    write_new(args.file, map_examples()[args.name])
    return MapWritten(args.name, args.file)


def example_view(written: MapWritten) -> View:
    generate_line = f'vtube tube generate {written.path} --out SCENE.toml'
    return View((f'map {written.name} written to {written.path}; generate its tube with: {generate_line}',))


COMMANDS = (
    Command(
        'tube generate', 'generate a regular tube from an obstacle map', generate_arguments, generate, generate_view
    ),
    Command(
        'tube example', 'write a shipped Robotarium obstacle map, to edit', example_arguments, example, example_view
    ),
)
