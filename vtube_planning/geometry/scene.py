"""Scenes: a virtual tube, the swarm's parameters and the planning options, read from a TOML file.

The paper's scenes A-D and two Robotarium scenes ship inside the package (``vtube_planning/scenes/*.toml``);
users write their own in the same format. Every table is checked strictly: an unknown key, a missing field or a
value of the wrong type raises `SceneError` naming the file, the table and the fix. The format:

    title = "..."                       # optional, one line
    description = "..."                 # optional

    [tube.center]                       # either pieces ...
    start_xy_m = [0.0, 0.0]             # optional, default [0, 0]
    heading_deg = 0.0                   # optional, default 0
    pieces = [{ kind = "line", length_m = 10.0 },
              { kind = "arc", radius_m = 15.0, angle_deg = 45.0 }]   # angle > 0 turns left
    # ... or waypoints = [[x, y], ...]  (a natural cubic spline, re-parameterised by arc length)

    [tube.width]
    start_m = 4.5                       # half-width at l = 0
    parts = [{ kind = "constant", length_m = 20.0 },
             { kind = "linear", length_m = 16.0, to_m = 1.2, corner_m = 1.5 },
             { kind = "smooth", length_m = 5.0, to_m = 1.0 },
             { kind = "constant" }]     # the last part may omit length_m: it fills the rest of the tube

    [swarm]                             # optional; any SwarmParams field, Table 1 defaults otherwise
    [planning]                          # optional; any PlanningOptions field (objective = "centre" | "last_out")
    [control]                           # optional; any ControlParams field (controller gains and options)
    [obstacles]                         # optional; discs = [{ center_m = [x, y], radius_m = r }], polygons =
                                        # [{ vertices_m = [[x, y], ...] }], images (geometry.occupancy): no cross-
                                        # section may meet one (proved on loading, obstacles.obstacle_certificate)
    [workspace]                         # optional; x_min_m, x_max_m, y_min_m, y_max_m, margin_m: the tube
                                        # boundaries must stay inside the rectangle by at least margin_m
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, fields, replace
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10 (ROS 2 Humble on Ubuntu 22.04)
    import tomli as tomllib

from vtube_planning._validate import is_real
from vtube_planning.errors import SceneError, VtubeError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece, CenterCurve, SplineCurve
from vtube_planning.geometry.obstacles import NO_OBSTACLES, Obstacles, certified_obstacles
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.geometry.workspace import Workspace
from vtube_planning.params import ControlParams, PlanningOptions, SwarmParams

_SCENE_PACKAGE = 'vtube_planning.scenes'


@dataclass(frozen=True)
class Derived:
    """A scene value derived by code rather than written in the file: its name, value and why (for ``scene show``).

    ``given`` is True when the file set the value itself, overriding the derivation (the reason then says what the
    derivation would have given)."""

    name: str
    value: float | int | str
    reason: str
    given: bool = False


@dataclass(frozen=True)
class Scene:
    """A planning scene: where the swarm flies and with which parameters.

    Attributes
    ----------
    name
        Short name (the file's stem for shipped scenes, e.g. ``'A'`` or ``'robotarium_curve'``).
    title, description
        Human-readable text from the file.
    tube
        The virtual tube.
    swarm
        The swarm's parameters.
    planning
        The planner's options.
    control
        The controller's gains and options.
    workspace
        Optional rectangle the tube fits in.
    source
        The file the scene was read from.
    text
        The file's content, as read (what provenance records and copies beside results).
    testbed
        The testbed the scene is declared for (``'robotarium'``: a ``[robotarium]`` table), or None.
    derived
        The values derived from the declaration, with their reasons (empty for a scene that writes them all).
    obstacles
        Obstacles around the tube (``[obstacles]``): drawn, and certified clear of every cross-section on loading.
    """

    name: str
    title: str
    description: str
    tube: VirtualTube
    swarm: SwarmParams
    planning: PlanningOptions
    control: ControlParams
    workspace: Workspace | None
    source: str
    text: str = ''
    testbed: str | None = None
    derived: tuple[Derived, ...] = ()
    obstacles: Obstacles = NO_OBSTACLES


def list_scenes() -> list[str]:
    """Names of the scenes shipped with the package, sorted."""
    files = resources.files(_SCENE_PACKAGE).iterdir()
    return sorted(f.name.removesuffix('.toml') for f in files if f.name.endswith('.toml'))


def load_scene(name_or_path: str | Path) -> Scene:
    """Load a shipped scene by name (``'A'``, ``'robotarium_curve'``) or a scene file by path.

    Raises
    ------
    SceneError
        If the scene is unknown, the file unreadable, or its content invalid; the message names the file.
    """
    path = Path(name_or_path)
    if path.suffix == '.toml' or path.exists():
        return scene_from_text(read_scene_file(path), name=path.stem, source=str(path))
    name, text = shipped_scene_text(str(name_or_path))
    return scene_from_text(text, name=name, source=f'<shipped>/{name}.toml')


def read_scene_file(path: Path) -> str:
    """A scene file's text; a folder, a missing file or text that is not UTF-8 raises `SceneError`."""
    if path.is_dir():
        msg = f'{str(path)!r} is a folder, not a scene file; give a path to a .toml file or a shipped scene name.'
        raise SceneError(msg)
    if not path.is_file():
        msg = f'scene file {str(path)!r} does not exist; give a path to a .toml file or a shipped scene name.'
        raise SceneError(msg)
    try:
        return path.read_text(encoding='utf-8')
    except UnicodeDecodeError as err:
        msg = f'scene file {str(path)!r} is not UTF-8 text ({err.reason} at byte {err.start}); save it as UTF-8.'
        raise SceneError(msg) from err


def shipped_scene_text(name: str) -> tuple[str, str]:
    """A shipped scene's name as spelled in the package and its TOML text (to copy and edit)."""
    shipped = {n.lower(): n for n in list_scenes()}
    if name.lower() not in shipped:
        msg = f'unknown scene {name!r}; shipped scenes are {list_scenes()}, or give a .toml path.'
        raise SceneError(msg)
    spelled = shipped[name.lower()]
    return spelled, (resources.files(_SCENE_PACKAGE) / f'{spelled}.toml').read_text(encoding='utf-8')


def scene_from_text(text: str, *, name: str, source: str) -> Scene:
    """Parse a scene from TOML text; ``source`` names it in error messages."""
    return replace(scene_from_data(scene_data(text, source), name=name, source=source), text=text)


def scene_data(text: str, source: str) -> dict[str, Any]:
    """The TOML tables of a scene's text (not yet checked); ``source`` names it in error messages."""
    try:
        data: dict[str, Any] = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        msg = f'{source}: not valid TOML ({err}).'
        raise SceneError(msg) from err
    return data


def scene_from_data(data: dict[str, Any], *, name: str, source: str) -> Scene:
    """A scene from its TOML tables, checked strictly; errors name ``source``."""
    try:
        return _build(data, tube_from_data(data, name=name, source=source), source=source)
    except SceneError:
        raise
    except VtubeError as err:
        msg = f'{source}: {err}'
        raise SceneError(msg) from err


def tube_from_data(data: dict[str, Any], *, name: str, source: str) -> VirtualTube:
    """The tube of a scene's TOML tables (the other tables are not read); errors name ``source``."""
    where = _Where(source)
    if 'tube' not in data:
        raise where.fail(
            "missing field 'tube' in the top level; add it (see the format in vtube_planning.geometry.scene)."
        )
    tube_table = where.table(data, 'tube')
    where.keys(tube_table, 'tube', required=('center', 'width'))
    center = _center(where.table(tube_table, 'center', 'tube'), where)
    width = _width(where.table(tube_table, 'width', 'tube'), center.length_m, where)
    try:
        return VirtualTube(center, width, name=name)
    except SceneError:
        raise
    except VtubeError as err:
        raise where.fail(str(err)) from err


def _build(data: dict[str, Any], tube: VirtualTube, *, source: str) -> Scene:
    where = _Where(source)
    where.keys(
        data,
        '',
        required=('tube',),
        optional=('title', 'description', 'swarm', 'planning', 'control', 'workspace', 'obstacles'),
    )
    name = tube.name
    swarm = SwarmParams(**_options(data, 'swarm', SwarmParams, where))
    planning = PlanningOptions(**_options(data, 'planning', PlanningOptions, where))
    control = ControlParams(**_options(data, 'control', ControlParams, where))
    workspace = None
    if 'workspace' in data:
        workspace = Workspace(**_options(data, 'workspace', Workspace, where))
        _check_workspace(tube, workspace, where)
    folder = Path(source).parent  # an image of [obstacles] is read relative to the scene file's folder
    try:
        obstacles = certified_obstacles(tube, data['obstacles'], folder) if 'obstacles' in data else NO_OBSTACLES
    except SceneError as err:
        raise where.fail(str(err)) from err
    return Scene(
        name=name,
        title=str(data.get('title', name)),
        description=str(data.get('description', '')).strip(),
        tube=tube,
        swarm=swarm,
        planning=planning,
        control=control,
        workspace=workspace,
        source=source,
        obstacles=obstacles,
    )


class _Where:
    """Strict access to the tables of one scene file, with messages that name the file and the table."""

    def __init__(self, source: str) -> None:
        self.source = source

    def fail(self, text: str) -> SceneError:
        return SceneError(f'{self.source}: {text}')

    def keys(
        self, table: dict[str, Any], path: str, *, required: tuple[str, ...] = (), optional: tuple[str, ...] = ()
    ) -> None:
        label = f'[{path}]' if path else 'the top level'
        unknown = sorted(set(table) - set(required) - set(optional))
        if unknown:
            allowed = ', '.join(required + optional)
            msg = f'unknown key {unknown[0]!r} in {label}; expected one of: {allowed}.'
            raise self.fail(msg)
        missing = [k for k in required if k not in table]
        if missing:
            msg = f'missing field {missing[0]!r} in {label}; add it (see the format in vtube_planning.geometry.scene).'
            raise self.fail(msg)

    def table(self, parent: dict[str, Any], key: str, parent_path: str = '') -> dict[str, Any]:
        value = parent[key]
        path = f'{parent_path}.{key}' if parent_path else key
        if not isinstance(value, dict):
            msg = f'[{path}] must be a table; got {type(value).__name__} {value!r}.'
            raise self.fail(msg)
        return value

    def number(self, table: dict[str, Any], key: str, path: str) -> float:
        value = table[key]
        if not is_real(value):
            msg = f'{key} in [{path}] must be a finite number; got {value!r}.'
            raise self.fail(msg)
        return float(value)


MAX_COORDINATE_M = 1e6
"""The largest coordinate a scene may use (1,000 km): beyond it the geometry's arithmetic loses its metres."""


def _center(table: dict[str, Any], where: _Where) -> CenterCurve:
    path = 'tube.center'
    if ('pieces' in table) == ('waypoints' in table):
        msg = f'[{path}] needs exactly one of pieces (lines and arcs) or waypoints (a spline).'
        raise where.fail(msg)
    if 'waypoints' in table:
        where.keys(table, path, required=('waypoints',))
        waypoints = table['waypoints']
        if not isinstance(waypoints, list) or not all(isinstance(p, list) and len(p) == 2 for p in waypoints):
            msg = f'waypoints in [{path}] must be a list of [x, y] pairs; got {waypoints!r}.'
            raise where.fail(msg)
        bad = [p for p in waypoints if not all(is_real(v) and abs(v) <= MAX_COORDINATE_M for v in p)]
        if bad:
            msg = f'waypoints in [{path}] must be numbers of metres within +-{MAX_COORDINATE_M:g}; {bad[0]!r} is not.'
            raise where.fail(msg)
        return SplineCurve(tuple((float(p[0]), float(p[1])) for p in waypoints))
    where.keys(table, path, required=('pieces',), optional=('start_xy_m', 'heading_deg'))
    pieces = table['pieces']
    if not isinstance(pieces, list) or not pieces:
        msg = f'pieces in [{path}] must be a non-empty list of tables.'
        raise where.fail(msg)
    start = table.get('start_xy_m', [0.0, 0.0])
    if (
        not isinstance(start, list)
        or len(start) != 2
        or not all(is_real(v) and abs(v) <= MAX_COORDINATE_M for v in start)
    ):
        msg = f'start_xy_m in [{path}] must be [x, y]; got {start!r}.'
        raise where.fail(msg)
    heading = where.number(table, 'heading_deg', path) if 'heading_deg' in table else 0.0
    return ArcPath(tuple(_piece(p, k, where) for k, p in enumerate(pieces)), tuple(start), math.radians(heading))


def _piece(piece: object, k: int, where: _Where) -> ArcPiece:
    path = f'tube.center.pieces[{k}]'
    if not isinstance(piece, dict) or piece.get('kind') not in ('line', 'arc'):
        msg = f'{path} must be a table with kind = "line" or "arc"; got {piece!r}.'
        raise where.fail(msg)
    if piece['kind'] == 'line':
        where.keys(piece, path, required=('kind', 'length_m'))
        return ArcPiece(_metres(piece, 'length_m', path, where))
    where.keys(piece, path, required=('kind', 'radius_m', 'angle_deg'))
    radius, angle = _metres(piece, 'radius_m', path, where), where.number(piece, 'angle_deg', path)
    if angle == 0.0 or radius <= 0.0:
        msg = f'{path}: an arc needs radius_m > 0 and angle_deg != 0 (positive turns left); got {radius}, {angle}.'
        raise where.fail(msg)
    return ArcPiece(radius * math.radians(abs(angle)), radius_m=radius, left=angle > 0)


def _metres(table: dict[str, Any], key: str, path: str, where: _Where) -> float:
    value = where.number(table, key, path)
    if abs(value) > MAX_COORDINATE_M:
        msg = f'{key} in [{path}] must be at most {MAX_COORDINATE_M:g} m; got {value:g}.'
        raise where.fail(msg)
    return value


def _width(table: dict[str, Any], length_m: float, where: _Where) -> WidthProfile:
    path = 'tube.width'
    where.keys(table, path, required=('start_m', 'parts'))
    parts = table['parts']
    if not isinstance(parts, list) or not parts:
        msg = f'parts in [{path}] must be a non-empty list of tables.'
        raise where.fail(msg)
    built: list[WidthPart] = []
    for k, part in enumerate(parts):
        part_path = f'{path}.parts[{k}]'
        if not isinstance(part, dict):
            msg = f'{part_path} must be a table such as {{ kind = "constant", length_m = 10.0 }}; got {part!r}.'
            raise where.fail(msg)
        last = k == len(parts) - 1
        where.keys(
            part,
            part_path,
            required=('kind',) if last else ('kind', 'length_m'),
            optional=('length_m', 'to_m', 'corner_m') if last else ('to_m', 'corner_m'),
        )
        values = {key: part[key] for key in ('length_m', 'to_m', 'corner_m') if key in part}
        if last and 'length_m' not in part:
            values['length_m'] = length_m - sum(p.length_m for p in built)
            if values['length_m'] <= 0.0:
                msg = (
                    f'the width parts before the last already cover {length_m - values["length_m"]:.3f} m of a '
                    f'{length_m:.3f} m tube; shorten them.'
                )
                raise where.fail(msg)
        built.append(WidthPart(part['kind'], **values))
    return WidthProfile(where.number(table, 'start_m', path), tuple(built))


def _options(data: dict[str, Any], key: str, cls: type, where: _Where) -> dict[str, Any]:
    if key not in data:
        return {}
    table = where.table(data, key)
    where.keys(table, key, optional=tuple(f.name for f in fields(cls) if f.init))
    return dict(table)


def _check_workspace(tube: VirtualTube, workspace: Workspace, where: _Where) -> None:
    grid = np.linspace(0.0, tube.length_m, 4001)
    for side, points in zip(('left', 'right'), tube.boundaries(grid), strict=True):
        clearance = workspace.clearance(points)
        k = int(np.argmin(clearance))
        if clearance[k] < workspace.margin_m:
            msg = (
                f'the {side} tube boundary at l = {grid[k]:.3f} m, point ({points[k, 0]:.3f}, {points[k, 1]:.3f}), '
                f'is {clearance[k]:.3f} m from the workspace edge, less than margin_m = {workspace.margin_m}; '
                'move or narrow the tube.'
            )
            raise where.fail(msg)
