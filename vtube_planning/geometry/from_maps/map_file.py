"""Map files: a scene file whose tube is to be generated, and the scene file the generator writes from it.

A map file is a scene file (`vtube_planning.geometry.scene`) with ``[tube.generate]`` in place of
``[tube.center]`` and ``[tube.width]``, a ``[workspace]`` (the map's rectangle) and ``[obstacles]``:

    [tube.generate]
    start_m = [2.0, 20.0]        # or start_region_m = [x_min, x_max, y_min, y_max]: the generator chooses the
    goal_m = [78.0, 20.0]        # node of the region the cheapest path joins (goal_region_m likewise)
    half_width_min_m = 1.0       # a passage with less room is refused
    half_width_max_m = 4.0
    margin_m = 0.3               # optional; every other key of TubeSpec is optional too (turn_radius_min_m
                                 # defaults to v_min^2 / a_n of the file's [swarm]: what the planner needs;
                                 # a Robotarium map file, with [robotarium], must give it)

`generated_scene` generates the tube (`generate_tube`) and returns
the file's text with ``[tube.generate]`` replaced by the tube's ``[tube.center]`` (lines and arcs) and
``[tube.width]`` (constant and linear parts), every number written exactly (``repr``): an ordinary scene file that
loads to the very tube generated, its obstacles certified again on loading.

``[obstacles]`` may hold occupancy images (``images = [{ file = "room.png", resolution_m = 0.05, origin_m = [x0,
y0] }]``, `vtube_planning.geometry.occupancy`; ``file`` relative to the map file's folder). The scene file
written keeps the map file's text but for those two tables; with images, its ``[obstacles]`` is written anew, each
``file`` relative to the folder the scene file is written to (absolute when it cannot be, on another drive), so
that it still finds the image.
"""

from __future__ import annotations

import json
import math
import re
import sys
from dataclasses import fields, replace
from pathlib import Path
from typing import Any

import numpy as np

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib

from vtube_planning._validate import is_real
from vtube_planning.errors import SceneError
from vtube_planning.geometry.centerline import ArcPath
from vtube_planning.geometry.from_maps.centre_path import Box, SearchGrid
from vtube_planning.geometry.from_maps.generate import GeneratedTube, TubeSpec, generate_tube
from vtube_planning.geometry.obstacles import Obstacles, obstacles_from_table
from vtube_planning.geometry.workspace import Workspace
from vtube_planning.params import SwarmParams

_TABLE = re.compile(r'^\s*\[')
_GENERATE = re.compile(r'^\s*\[\s*tube\s*\.\s*generate\s*\]\s*(#.*)?$')
_OBSTACLES = re.compile(r'^\s*\[\[?\s*obstacles\s*[.\]]')


def map_spec(data: dict[str, Any], source: str) -> TubeSpec:
    """The generation spec of a map file's tables; [`SceneError`][vtube_planning.errors.SceneError] names what is
    missing or wrong."""
    tube = data.get('tube')
    if not isinstance(tube, dict) or set(tube) != {'generate'} or not isinstance(tube['generate'], dict):
        msg = f'{source}: a map file has [tube.generate] and no other [tube] table (see vtube_planning.geometry.from_maps.map_file).'
        raise SceneError(msg)
    table = dict(tube['generate'])
    allowed = {f.name for f in fields(TubeSpec)} - {'bounds', 'obstacles'} | set(_REGIONS.values())
    unknown = sorted(set(table) - allowed)
    if unknown:
        msg = f'{source}: unknown key {unknown[0]!r} in [tube.generate]; expected one of: {", ".join(sorted(allowed))}.'
        raise SceneError(msg)
    for point, region in _REGIONS.items():
        if (point in table) == (region in table):
            msg = f'{source}: give one of {point!r} ([x, y]) and {region!r} ([x_min, x_max, y_min, y_max]) in [tube.generate].'
            raise SceneError(msg)
    for key in ('half_width_min_m', 'half_width_max_m'):
        if key not in table:
            msg = f'{source}: missing field {key!r} in [tube.generate]; add it.'
            raise SceneError(msg)
    if 'robotarium' in data and 'turn_radius_min_m' not in table:
        msg = (
            f"{source}: a Robotarium map file needs turn_radius_min_m in [tube.generate] (the robots' v_min^2 / a_n; "
            "the shipped maps, `vtube tube example`, use 0.6): the default, from [swarm], is the paper's scale."
        )
        raise SceneError(msg)
    if 'workspace' not in data:
        msg = f'{source}: a map file needs [workspace] (x_min_m, x_max_m, y_min_m, y_max_m, margin_m): the map.'
        raise SceneError(msg)
    try:
        bounds = Workspace(**data['workspace'])
        obstacles = obstacles_from_table(data['obstacles'], Path(source).parent) if 'obstacles' in data else Obstacles()
        _require_coverage(bounds, obstacles, source)
        if 'turn_radius_min_m' not in table:
            swarm = SwarmParams(**{k: v for k, v in data.get('swarm', {}).items() if k in _SWARM_FIELDS})
            table['turn_radius_min_m'] = swarm.v_min_mps**2 / swarm.a_n_mps2
        boxes = {point: _box(table.pop(region), region) for point, region in _REGIONS.items() if region in table}
        for point, box in boxes.items():  # a first guess, which decides nothing but where the map's edge is relaxed
            table[point] = (0.5 * (box[0] + box[1]), 0.5 * (box[2] + box[3]))
        table['start_m'], table['goal_m'] = tuple(table['start_m']), tuple(table['goal_m'])
        spec = TubeSpec(bounds=bounds, obstacles=obstacles, **table)
        if not boxes:
            return spec
        start, goal = SearchGrid(spec).cheapest_ends(
            boxes.get('start_m', spec.start_m), boxes.get('goal_m', spec.goal_m)
        )
        return replace(spec, start_m=start, goal_m=goal)
    except (TypeError, ValueError) as err:
        msg = f'{source}: {err}'
        raise SceneError(msg) from err


_SWARM_FIELDS = {f.name for f in fields(SwarmParams)}
_REGIONS = {'start_m': 'start_region_m', 'goal_m': 'goal_region_m'}
"""Each end is a point, or a region (a rectangle) in which the generator chooses it (`map_spec`)."""


def _box(value: object, key: str) -> Box:
    """A region [x_min, x_max, y_min, y_max] of [tube.generate], checked."""
    if not (isinstance(value, list) and len(value) == 4 and all(is_real(v) for v in value)):
        raise ValueError(f'{key} must be [x_min, x_max, y_min, y_max], finite numbers; got {value!r}')
    x0, x1, y0, y1 = (float(v) for v in value)
    if x0 > x1 or y0 > y1:
        raise ValueError(
            f'{key} must be [x_min, x_max, y_min, y_max] with x_min <= x_max, y_min <= y_max; got {value!r}'
        )
    return x0, x1, y0, y1


def is_map_file(text: str) -> bool:
    """Whether a scene file's ``text`` is a map file: it has a [tube.generate] table."""
    return any(_GENERATE.match(line) for line in text.splitlines())


def generated_scene(text: str, source: str, folder: Path | None = None) -> tuple[str, GeneratedTube]:
    """The scene file generated from a map file's ``text`` (module doc), to be written in ``folder`` (the map
    file's folder by default), and the generated tube."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        msg = f'{source}: not valid TOML: {err}'
        raise SceneError(msg) from err
    spec = map_spec(data, source)
    generated = generate_tube(spec)
    images = bool(spec.obstacles.images)
    lines, skipping = [], False
    for line in text.splitlines():
        if _GENERATE.match(line) or (images and _OBSTACLES.match(line)):
            skipping = True
            lines.extend(_tube_tables(generated, spec) if _GENERATE.match(line) else [])
            continue
        if skipping and _TABLE.match(line):
            skipping = False
        if not skipping:
            lines.append(line)
    scene = '\n'.join(lines).rstrip() + '\n'
    if images:
        out = Path(source).parent if folder is None else Path(folder)
        scene += '\n' + _obstacles_table(spec.obstacles, out)
        try:
            same = obstacles_from_table(tomllib.loads(scene).get('obstacles'), out) == spec.obstacles
        except tomllib.TOMLDecodeError:
            same = False
        if not same:
            msg = f'{source}: write [obstacles] as one table [obstacles] with discs, polygons, images = [...].'
            raise SceneError(msg)
    return scene, generated


def _require_coverage(bounds: Workspace, obstacles: Obstacles, source: str, samples: int = 201) -> None:
    """Refuse a map whose occupancy images do not cover its workspace (checked on a grid of ``samples`` squared
    points): space outside every image is space nobody mapped, and no obstacle of it would be seen."""
    if not obstacles.images:
        return
    x = np.linspace(bounds.x_min_m, bounds.x_max_m, samples)
    y = np.linspace(bounds.y_min_m, bounds.y_max_m, samples)
    xx, yy = np.meshgrid(x, y)
    covered = np.zeros(xx.shape, dtype=bool)
    for image in obstacles.images:
        x0, x1, y0, y1 = image.extent_m
        covered |= (xx >= x0 - 1e-9) & (xx <= x1 + 1e-9) & (yy >= y0 - 1e-9) & (yy <= y1 + 1e-9)
    if covered.all():
        return
    spans = '; '.join(
        f'{Path(image.source).name or "an image"} spans x in [{image.extent_m[0]:.6g}, {image.extent_m[1]:.6g}], '
        f'y in [{image.extent_m[2]:.6g}, {image.extent_m[3]:.6g}] m ({image.occupied.shape[1]} x '
        f'{image.occupied.shape[0]} pixels at resolution_m = {image.resolution_m:g})'
        for image in obstacles.images
    )
    msg = (
        f'{source}: the occupancy images cover {100 * covered.mean():.1f} % of [workspace] ({bounds}), where nothing '
        f'outside them would be seen: {spans}; correct resolution_m or origin_m of the image, or shrink [workspace] '
        'to the image.'
    )
    raise SceneError(msg)


def _obstacles_table(obstacles: Obstacles, folder: Path) -> str:
    """``[obstacles]`` in TOML, numbers exact, an image's ``file`` relative to ``folder`` when it can be."""
    free = [image for image in obstacles.images if image.unknown_free]
    lines = [
        '# unknown cells of the images count as FREE here (unknown = "free"): the tube may cross unmapped space'
    ] * bool(free)
    lines += ['[obstacles]']
    for kind, entries in obstacles.table(folder).items():
        lines.append(f'{kind} = [')
        for entry in entries:
            values = ', '.join(f'{key} = {_toml(value)}' for key, value in entry.items())
            lines.append(f'    {{ {values} }},')
        lines.append(']')
    return '\n'.join(lines) + '\n'


def _toml(value: object) -> str:
    """A number (exact), a string or a list of them in TOML."""
    if isinstance(value, str):
        return json.dumps(value)  # a JSON string is a TOML basic string
    if isinstance(value, (list, tuple)):
        return '[' + ', '.join(_toml(v) for v in value) + ']'
    return repr(float(value)) if isinstance(value, float) else repr(value)


def _tube_tables(generated: GeneratedTube, spec: TubeSpec) -> list[str]:
    """``[tube.center]`` and ``[tube.width]`` of the generated tube, numbers exact."""
    center = generated.tube.center
    if not isinstance(center, ArcPath):  # the generator makes lines and arcs
        msg = 'the generated centre curve is not a path of lines and arcs.'
        raise SceneError(msg)
    x, y = center.start_xy_m
    lines = [
        (
            f'# generated by `vtube tube generate` from [tube.generate] start_m = {list(spec.start_m)!r}, goal_m = '
            f'{list(spec.goal_m)!r}, half_width_min_m = {spec.half_width_min_m!r}, half_width_max_m = '
            f'{spec.half_width_max_m!r}, margin_m = {spec.margin_m!r}, turn_radius_min_m = {spec.turn_radius_min_m!r}'
            + _ends(spec, generated.lead_m)
        ),
        '[tube.center]',
        f'start_xy_m = [{x!r}, {y!r}]',
        f'heading_deg = {math.degrees(center.heading_rad)!r}',
        'pieces = [',
    ]
    for piece in center.pieces:
        if piece.radius_m is None:
            lines.append(f'    {{ kind = "line", length_m = {piece.length_m!r} }},')
        else:
            angle = math.degrees(piece.length_m / piece.radius_m) * (1.0 if piece.left else -1.0)
            lines.append(f'    {{ kind = "arc", radius_m = {piece.radius_m!r}, angle_deg = {angle!r} }},')
    width = generated.tube.width
    lines += [']', '', '[tube.width]', f'start_m = {width.start_m!r}', 'parts = [']
    for part in width.parts:
        to = f', to_m = {part.to_m!r}' if part.to_m is not None else ''
        corner = f', corner_m = {part.corner_m!r}' if part.corner_m is not None else ''
        lines.append(f'    {{ kind = "{part.kind}", length_m = {part.length_m!r}{to}{corner} }},')
    return [*lines, ']', '']


def _ends(spec: TubeSpec, lead_m: float) -> str:
    """The headings given and the lead held along them (fitted by the generator when lead_m was not given)."""
    if not spec.headed:
        return ''
    given = [
        f'{k} = {getattr(spec, k)!r}' for k in ('start_heading_deg', 'goal_heading_deg') if getattr(spec, k) is not None
    ]
    return ', ' + ', '.join(given) + f', lead_m = {lead_m!r}' + (' (fitted: not given)' if spec.lead_m == 0.0 else '')
