"""``vtube scene list|show|export``: the shipped scenes, a scene's summary and figure, a copy to edit."""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from vtube.cli.arguments import figure_file
from vtube.cli.command import EXIT_FAILED, EXIT_OK, BadInput, Command, View
from vtube_planning.files import write_atomically

if TYPE_CHECKING:
    from robotarium_exp.fit import Fit
    from vtube_planning.geometry.scene import Scene


@dataclass(frozen=True)
class SceneList:
    """The shipped scenes: name, length and title of each."""

    scenes: tuple[tuple[str, float, str], ...]


@dataclass(frozen=True)
class SceneShown:
    """A scene, its tube's summary, the Robotarium's verdict (None: not a Robotarium scene) and the figure written
    (None: none asked for)."""

    scene: Scene
    summary: dict[str, float]
    fit: Fit | None
    figure: Path | None


@dataclass(frozen=True)
class SceneExported:
    """A shipped scene's file written to ``path``."""

    name: str
    path: Path


def no_arguments(parser: argparse.ArgumentParser) -> None:
    """A command without options."""


def shipped(args: argparse.Namespace) -> SceneList:
    from robotarium_exp.scene import list_scenes, load_scene

    scenes = [load_scene(name) for name in list_scenes()]
    return SceneList(tuple((scene.name, scene.tube.length_m, scene.title) for scene in scenes))


def list_view(result: SceneList) -> View:
    return View(tuple(f'{name:<22} {length:7.2f} m  {title}' for name, length, title in result.scenes))


def show_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('scene', help='a shipped scene name (see `vtube scene list`) or a .toml file')
    parser.add_argument('--out', type=Path, default=None, help='write the figure here (e.g. scene.png)')


def show(args: argparse.Namespace) -> SceneShown:
    from robotarium_exp.fit import robotarium_fit
    from robotarium_exp.plots import scene_figure as robotarium_figure
    from robotarium_exp.scene import load_scene
    from vtube_planning.plots import save_figure, scene_figure

    if args.out is not None:
        figure_file(args.out)
    scene = load_scene(args.scene)
    fit = robotarium_fit(scene) if scene.testbed == 'robotarium' else None
    figure = None
    if args.out is not None:
        figure = save_figure(scene_figure(scene) if fit is None else robotarium_figure(scene, fit), args.out)
    return SceneShown(scene, scene.tube.summary(), fit, figure)


def show_view(result: SceneShown) -> View:
    scene, summary, swarm = result.scene, result.summary, result.scene.swarm
    source = scene.source
    if source.startswith('<shipped>'):
        source += f'  (vtube scene export {scene.name} FILE.toml writes a copy to edit)'
    lines = [
        f'scene {scene.name}: {scene.title}',
        f'  source                {source}',
        f'  length                {summary["length_m"]:.3f} m',
        f'  half-width            {summary["half_width_min_m"]:.3f} .. {summary["half_width_max_m"]:.3f} m',
        f'  min curvature radius  {summary["curvature_radius_min_m"]:.3f} m',
        f'  max lambda |kappa|    {summary["lambda_kappa_max"]:.3f}  (regular below 1)',
        f'  area                  {summary["area_m2"]:.3f} m^2',
        (
            f'  swarm                 N = {swarm.n_robots}, v in [{swarm.v_min_mps:g}, {swarm.v_max_mps:g}] m/s, '
            f'r_p/r_s/r_a = {swarm.r_p_m:g}/{swarm.r_s_m:g}/{swarm.r_a_m:g} m, rho_d = {swarm.rho_d_per_m2:g}, '
            f'rho_max = {swarm.rho_max_per_m2:g} /m^2, a_rho = {swarm.a_rho:.4g} /m^2/s'
        ),
    ]
    if scene.derived:
        lines.append(f'  values of the [{scene.testbed}] declaration (set in the file or derived, and why):')
        lines.extend(f'    {d.name:<18} {d.value!s:<12} {d.reason}' for d in scene.derived)
    if result.figure is not None:
        lines.append(f'  figure                {result.figure}')
    if result.fit is None:
        return View(tuple(lines))
    lines.append(f'  Robotarium            {result.fit.reason}')
    lines.extend(f'                        also: {misfit}' for misfit in result.fit.misfits[1:])
    return View(tuple(lines), None, EXIT_OK if result.fit.fits else EXIT_FAILED)


def export_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('scene', help='a shipped scene name (see `vtube scene list`)')
    parser.add_argument('file', type=Path, help='the .toml file to write (must not exist)')


def export(args: argparse.Namespace) -> SceneExported:
    from robotarium_exp.scene import shipped_scene_text

    spelled, text = shipped_scene_text(args.scene)
    path: Path = args.file
    if path.exists():
        msg = f'{path} exists; give another file name (nothing was written).'
        raise BadInput(msg)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_atomically(path, text)
    return SceneExported(spelled, path)


def export_view(result: SceneExported) -> View:
    return View(
        (f'scene {result.name} written to {result.path}; edit it and pass the file where a scene is asked for',)
    )


COMMANDS = (
    Command('scene list', 'list the shipped scenes', no_arguments, shipped, list_view),
    Command('scene show', "print a scene's summary and draw it", show_arguments, show, show_view),
    Command('scene export', "write a shipped scene's file, to edit", export_arguments, export, export_view),
)
