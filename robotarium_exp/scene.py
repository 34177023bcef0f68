"""Robotarium scenes: a tube and a number of robots, every other value derived (`robotarium_exp.design`).

A Robotarium scene is an ordinary scene file (``vtube_planning.geometry.scene``) whose ``[robotarium]`` table
declares the experiment:

    [robotarium]
    n_robots = 10          # 1 to 20

The swarm's speeds, accelerations and radii, the planner's options and the controller's gains are the
Robotarium's (`ROBOTARIUM_VALUES`) or derived from the tube and N (`derived_values`); a value written
in the file's ``[swarm]``, ``[planning]`` or ``[control]`` table overrides either, and ``vtube scene show`` says
so. [`load_scene`][robotarium_exp.scene.load_scene] loads every scene the command line takes: the paper's, the
Robotarium's, or a file.
"""

from __future__ import annotations

import math
from dataclasses import replace
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.design import (
    LOOK_AHEAD_BANDS,
    R_S_M,
    first_narrowing,
    formation_density,
    look_ahead,
    start_formation,
)
from robotarium_exp.rps.testbed_model import FITTED
from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.errors import SceneError
from vtube_planning.geometry import scene as planning_scenes
from vtube_planning.geometry.scene import Derived, Scene
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.workspace import Workspace
from vtube_planning.onboard.density import swarm_density

_SCENE_PACKAGE = 'robotarium_exp.scenes'
TABLE = 'robotarium'
"""The table that declares a Robotarium experiment."""

Values = dict[str, dict[str, tuple[float | int | str | bool, str]]]
"""Table -> key -> (value, reason)."""

ROBOTARIUM_VALUES: Values = {
    'swarm': {
        'v_min_mps': (0.04, 'v_min / v_max = 0.33 (Table 1 has 0.4)'),
        'v_max_mps': (0.12, 'below 0.134 m/s, what a GRITSbot always realises through the map at d = 0.05 m'),
        'a_v_mps2': (0.02, 'from v_min to v_max in 0.32 m, a small part of the tube as in Table 1'),
        'a_n_mps2': (0.02, 'as a_v'),
        'r_p_m': (0.07, "covers the testbed's collision test, 0.135 m between centres"),
    },
    'planning': {
        'grid_step_m': (0.0125, 'about 200 intervals over a tube of the arena'),
        'predictive_model': ('local_width', '(p7) read with the local width (documentation: Theory)'),
    },
    'control': {
        'avoidance_gain': (5e-4, "the paper's gains scaled by v_max times the interaction band squared"),
        'keeping_gain': (5e-4, 'as the avoidance gain'),
        'k_ra_m3ps': (0.02, 'r_a moves 0.02 m/s per robot/m^2 of density above the plan'),
        'r_a_max_m': (0.5, "the band can reach the narrowing's density in the wide part"),
        'feedforward': (True, "the plan's dip raises r_a ahead of the density error"),
        'plan_at': ('center', "the plan is made for the swarm's centre (documentation: Theory, A16)"),
        'stretch_gain_mps': (
            0.3,
            (
                'the swarm lengthens or shortens along the tube as its density is above or below the plan: the rows '
                'thin out where the plan dips (documentation: Theory, §2.9)'
            ),
        ),
        'compensate_delay_steps': (
            0.5 * (FITTED.delay_v_steps + FITTED.delay_omega_steps),
            (
                "the real robots' command delay (testbed model 'fitted', robotarium_exp.rps.testbed_model): the step acts on "
                'where the robots will be when its command arrives (documentation: Theory, §9)'
            ),
        ),
        'compensate_lag_s': (FITTED.lag_s, "the real robots' first-order lag, compensated with the delay"),
    },
}
"""The Robotarium's values of every Robotarium scene, with their reasons (docs/howto/robotarium_run.md)."""


def list_scenes() -> list[str]:
    """Names of every shipped scene (the paper's and the Robotarium's), sorted."""
    files = resources.files(_SCENE_PACKAGE).iterdir()
    ours = [f.name.removesuffix('.toml') for f in files if f.name.endswith('.toml')]
    return sorted(planning_scenes.list_scenes() + ours)


def shipped_scene_text(name: str) -> tuple[str, str]:
    """A shipped scene's name as spelled and its TOML text (to copy and edit)."""
    files = {f.name.removesuffix('.toml').lower(): f for f in resources.files(_SCENE_PACKAGE).iterdir()}
    if name.lower() in files:
        file = files[name.lower()]
        return file.name.removesuffix('.toml'), file.read_text(encoding='utf-8')
    try:
        return planning_scenes.shipped_scene_text(name)
    except SceneError:
        msg = f'unknown scene {name!r}; shipped scenes are {list_scenes()}, or give a .toml path.'
        raise SceneError(msg) from None


def load_scene(name_or_path: str | Path, *, n_robots: int | None = None) -> Scene:
    """Load a shipped scene by name or a scene file; a ``[robotarium]`` table derives the rest (module doc).

    ``n_robots`` replaces the declared number of robots (of a Robotarium scene only).
    """
    path = Path(name_or_path)
    if path.suffix == '.toml' or path.exists():
        text = planning_scenes.read_scene_file(path)
        name, source = path.stem, str(path)
    else:
        name, text = shipped_scene_text(str(name_or_path))
        source = f'<shipped>/{name}.toml'
    data = planning_scenes.scene_data(text, source)
    if TABLE not in data:
        if n_robots is not None:
            msg = f'{source}: n_robots can be changed only in a Robotarium scene (one with a [{TABLE}] table).'
            raise SceneError(msg)
        return replace(planning_scenes.scene_from_data(data, name=name, source=source), text=text)
    return replace(robotarium_scene(data, name=name, source=source, n_robots=n_robots), text=text)


def robotarium_scene(data: dict[str, Any], *, name: str, source: str, n_robots: int | None = None) -> Scene:
    """The scene of a file's tables with a ``[robotarium]`` table: the Robotarium's values, the derived ones,
    then the file's own, which win."""
    declared = dict(data)
    n = _declared_robots({'n_robots': n_robots} if n_robots is not None else declared[TABLE], source)
    declared.pop(TABLE, None)
    tube = planning_scenes.tube_from_data(declared, name=name, source=source)
    values = {
        table: {**ROBOTARIUM_VALUES.get(table, {}), **derived} for table, derived in derived_values(tube, n).items()
    }
    derived: list[Derived] = []
    for table, entries in values.items():
        given = declared.get(table, {})
        if not isinstance(given, dict):
            msg = f'{source}: [{table}] must be a table; got {given!r}.'
            raise SceneError(msg)
        for key, (value, reason) in entries.items():
            if key in given:
                derived.append(Derived(key, given[key], f'set in the file (derived: {value}, {reason})', given=True))
            else:
                derived.append(Derived(key, value, reason))
        declared[table] = {**{key: value for key, (value, _) in entries.items()}, **given}
    scene = planning_scenes.scene_from_data(declared, name=name, source=source)
    workspace = scene.workspace or Workspace(*ROBOTARIUM.arena_m, margin_m=ROBOTARIUM.arena_margin_m)
    return replace(scene, workspace=workspace, testbed='robotarium', derived=tuple(derived))


def _declared_robots(table: object, source: str) -> int:
    """The number of robots a ``[robotarium]`` table declares, checked."""
    if not isinstance(table, dict) or set(table) != {'n_robots'}:
        msg = f'{source}: [{TABLE}] takes exactly one key, n_robots (1 to {ROBOTARIUM.max_robots}); got {table!r}.'
        raise SceneError(msg)
    n = table['n_robots']
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        msg = f'{source}: n_robots in [{TABLE}] must be a whole number >= 1 (the testbed has {ROBOTARIUM.max_robots}); got {n!r}.'
        raise SceneError(msg)
    return n


def derived_values(tube: VirtualTube, n_robots: int) -> Values:
    """The values derived from the tube and N, with their reasons (module doc of `robotarium_exp.design`)."""
    spacing = ROBOTARIUM.ic_spacing_m
    r_a = round(spacing - R_S_M, 6)
    formation = start_formation(tube, n_robots)
    rho_max = round(1.0 / (2.0 * math.pi * R_S_M**2), 2)
    if formation.problem is None:
        rho = round(formation_density(tube, formation, r_a), 2)
        where = (
            f'packed in no rows, {formation.length_m:.2f} m long (robotarium_exp.packing)'
            if formation.packed
            else f'{formation.rows} row(s) of up to {formation.columns}, {formation.length_m:.2f} m long'
        )
        if formation.queue:
            queued = int(np.count_nonzero(tube.project(formation.poses[:2]).l_m < 0.0))
            where += f', the entry queue: {queued} behind the entrance (documentation: Theory §12)'
        rho_reason = f'the start formation ({where}) under the density measure: the swarm starts on its plan'
        length = formation.length_m
    else:
        rho = min(rho_max, round(swarm_density(tube, [0.0] * n_robots, r_a), 2))
        rho_reason = f'no start formation ({formation.problem}): N robots abreast at the entrance'
        length = 0.0
    narrowing = first_narrowing(tube)
    ahead = narrowing.length_m if narrowing is not None else 0.0
    where = f'the narrowing from l = {narrowing.start_m:.2f} m ({ahead:.2f} m)' if narrowing else 'no narrowing'
    look_reason = (
        f'{where} plus the formation ({length:.2f} m) plus {LOOK_AHEAD_BANDS} bands ({spacing} m each): the density '
        'change the plan asks before the narrowing is one the rows can make (robotarium_exp.design.look_ahead, to 5 cm)'
    )
    return {
        'swarm': {
            'n_robots': (n_robots, f'[{TABLE}] n_robots'),
            'r_s_m': (R_S_M, 'the law keeps 2 r_s = 0.2 m between control points, as the safety filter does'),
            'r_a_m': (r_a, f'r_s + r_a = {spacing} m, the formation spacing: the swarm starts at rest in the law'),
            'rho_d_per_m2': (rho, rho_reason),
            'rho_max_per_m2': (rho_max, '1 / (2 pi r_s^2), the formula that reproduces Table 1'),
        },
        'planning': {
            'lookahead_m': (look_ahead(ahead, length), look_reason),
            'rho0_per_m2': (rho, 'rho_d: the start formation'),
        },
        'control': {},
    }
