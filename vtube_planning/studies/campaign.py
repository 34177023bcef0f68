"""Campaigns: a study declared as axes, run anywhere, streamed to disk, resumable.

A campaign (a TOML file for ``vtube campaign run``, or built by ``vtube study`` and ``vtube ablation``) names the
values of each axis of `Point` (scene, random map, mode, swarm size, seed, robot model,
saturation and the faults), the metrics to keep and what every run shares (`RunSettings`):

    name = "faults"
    out = "results/faults"          # the output folder, relative to this file (--out overrides it)
    metrics = ["passing_time_s", "min_distance_m", "collision_pairs", "tube_violation_steps", "completed"]

    [axes]
    scene = ["C", "D"]
    mode = ["planning", "no planning"]
    seed = 10                       # seeds 0..9; or a list [0, 1, 2], or a range "100-109" (also "0-4,10")
    pose_noise_m = [0.0, 0.02, 0.05]
    # map = ["bottleneck"]          # fly the scene's swarm through tubes generated on random maps instead
    # map_seed = [0, 2, 3]          # (vtube_planning.geometry.from_maps.maps; also map_clutter, map_width_m)

    [settings]
    failure_at = 0.5                # where a failing robot fails, times the tube's length

A top-level ``confirm_seeds = [100, 101, ...]`` runs those fresh seeds too, in every grid; the report pools them with
the grid's seeds, unless ``held_out = true``: then it tests them only on the claims the grid's seeds found (a
replication). A ``[families]`` table names the claims the report adjusts together (`vtube_planning.studies.judging`):

    [families.faster]
    comparisons = ["planning - no planning"]
    metrics = ["passing_time_s"]
    pose_noise_m = [0.0]

Several grids (``[[grids]]`` tables of axes instead of one ``[axes]``, as ``vtube study`` builds for baselines
flown on some scenes only) make one campaign whose runs are their products, in turn. Each run has a stable key (a
hash of everything that decides the run). Runs are made by `vtube_planning.studies.campaign_runner` and stored in the
campaign's folder (`vtube_planning.studies.campaign_store`).
"""

from __future__ import annotations

import hashlib
import itertools
import json
import sys
from collections.abc import Iterable, Mapping
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from vtube_planning._validate import is_real
from vtube_planning.errors import VtubeError
from vtube_planning.geometry.from_maps.maps import CLUTTER, FAMILIES, WIDTH_M, WIDTH_RANGE_M
from vtube_planning.geometry.scene import load_scene
from vtube_planning.onboard import SATURATIONS
from vtube_planning.studies import study
from vtube_planning.studies.judging import Family, FamilyError, Judging, families_from_toml
from vtube_planning.studies.seeds import SeedsError, parse_seeds
from vtube_planning.studies.study import Point, RunSettings
from vtube_planning.swarm.faults import FAILURE_MODES

if sys.version_info >= (3, 11):
    import tomllib as _toml
else:
    import tomli as _toml


class CampaignError(VtubeError, ValueError):
    """A campaign that cannot be expanded or run: an unknown axis or metric, an empty grid, another campaign's folder."""


AXES: dict[str, type] = {'scene': str, 'map': str, 'map_seed': int, 'map_clutter': int, 'map_width_m': float}
AXES |= {'narrowest_m': float, 'n_robots': int, 'model': str, 'saturation': str, 'pose_noise_m': float}
AXES |= {'latency_steps': int, 'lag_s': float, 'compensation': str, 'failure': str, 'dropout': float}
AXES |= {'controller': str, 'seed': int, 'mode': str}
"""The axes (the fields of `Point`) in the order runs are expanded: a cell's modes and seeds are adjacent."""
METRICS: dict[str, type] = {
    'passing_time_s': float,
    'min_distance_m': float,
    'collision_pairs': int,
    'incursion_depth_m': float,
    'tube_violation_steps': int,
    'completed': bool,
    'passed_share': float,
    'density_error_per_m2': float,
    'reversing_share': float,
    'nmpc_converged_share': float,
}
"""What a run measures (`run_point`), and its type in the table."""
_CHOICES = {
    'mode': (*study.ABLATIONS, *study.REPLANNING_MODES, *study.FREEDOM_MODES, *study.BASELINE_MODES),
    'model': tuple(study.MODELS),
    'controller': study.CONTROLLERS,
    'saturation': SATURATIONS,
    'failure': ('none', *FAILURE_MODES),
    'compensation': study.COMPENSATIONS,
    'map': ('none', *FAMILIES),
}


Grid = Mapping[str, tuple[Any, ...]]
"""The values of each axis of one grid (missing: `Point`'s default; ``n_robots`` and ``saturation`` missing:
each scene's own)."""


@dataclass(frozen=True)
class Campaign:
    """A study: one or more grids (their runs in turn, each run once), the metrics kept, the settings every run
    shares."""

    grids: tuple[Grid, ...]
    metrics: tuple[str, ...] = tuple(METRICS)
    settings: RunSettings = field(default_factory=RunSettings)
    name: str = 'campaign'
    out: Path | None = None
    """Where it runs unless told otherwise (``out`` in the file, relative to it); not part of what it is."""
    confirm_seeds: tuple[int, ...] = ()
    """Fresh seeds, run in every grid besides its own: pooled with the others, or ``held_out``."""
    families: tuple[Family, ...] = ()
    """The families of claims the report adjusts together (`vtube_planning.studies.judging`)."""
    held_out: bool = False
    """Whether the report tests the confirm_seeds apart, only on the claims the others found."""
    base: Path | None = field(default=None, compare=False)
    """The campaign file's folder, which its scene files are named from (None: the working directory); not part of
    what it is."""

    def __post_init__(self) -> None:
        if not self.grids:
            msg = 'the campaign has no grid: give an [axes] table, e.g. [axes] then scene = ["C", "D"].'
            raise CampaignError(msg)
        for grid in self.grids:
            unknown = [axis for axis in grid if axis not in AXES]
            if unknown:
                msg = f'unknown axis {unknown[0]!r}; the axes are {", ".join(AXES)}.'
                raise CampaignError(msg)
            if 'scene' not in grid:
                msg = 'a grid names no scene: give axes.scene, e.g. scene = ["C", "D"].'
                raise CampaignError(msg)
            for axis, values in grid.items():
                _check_values(axis, values, self.base)
        wrong = [m for m in self.metrics if m not in METRICS]
        if wrong or not self.metrics:
            msg = f'unknown metric {wrong[0]!r}' if wrong else 'the campaign keeps no metric'
            raise CampaignError(f'{msg}; choose from {", ".join(METRICS)}.')
        _check_settings(self.settings)
        for family in self.families:
            _check_family(family)
        if self.held_out and not self.confirm_seeds:
            msg = 'held_out = true needs seeds to hold out: give confirm_seeds, e.g. confirm_seeds = "100-109".'
            raise CampaignError(msg)
        if self.confirm_seeds:
            _check_values('seed', self.confirm_seeds)
            reused = sorted({s for g in self.grids for s in g.get('seed', (0,))} & set(self.confirm_seeds))
            if reused:
                msg = (
                    f'confirm_seeds must be fresh seeds, not among the seeds the grids run (axes.seed): {reused} '
                    'are in both; give seeds the grids do not run, e.g. confirm_seeds = "100-109".'
                )
                raise CampaignError(msg)

    @classmethod
    def from_toml(cls, path: Path) -> Campaign:
        """Read a campaign file (see the module's documentation); scene files are found relative to it."""
        try:
            data = _toml.loads(path.read_text(encoding='utf-8'))
        except FileNotFoundError as err:
            msg = f'campaign file {str(path)!r} does not exist; give the path to a .toml campaign file.'
            raise CampaignError(msg) from err
        except (_toml.TOMLDecodeError, UnicodeDecodeError) as err:
            msg = f'{path}: not a valid TOML file ({" ".join(str(err).split())}).'
            raise CampaignError(msg) from err
        try:
            return cls.from_dict(data, base=path.parent)
        except CampaignError as err:
            raise CampaignError(f'{path}: {err}') from err

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], base: Path | None = None) -> Campaign:
        """A campaign from its parsed TOML (or `to_json`); relative scene paths name files in ``base``."""
        unknown = [k for k in data if k not in KEYS]
        if unknown:
            msg = (
                f'unknown key {unknown[0]!r}; a campaign has name, out, axes (or grids), metrics, settings, '
                'confirm_seeds, held_out and families.'
            )
            raise CampaignError(msg)
        if ('axes' in data) == ('grids' in data):
            raise CampaignError('give the axes once: one [axes] table, or several [[grids]] tables.')
        grids = [data['axes']] if 'axes' in data else data['grids']
        settings = data.get('settings', {})
        tables = isinstance(grids, list) and all(isinstance(g, Mapping) for g in grids)
        if not tables or not isinstance(settings, Mapping):
            msg = '[axes] and [settings] must be tables, like [axes] then scene = ["C", "D"] on the next line.'
            raise CampaignError(msg)
        known = {f.name for f in fields(RunSettings)}
        extra = [k for k in settings if k not in known]
        if extra:
            msg = f'unknown setting {extra[0]!r}; the settings are {", ".join(sorted(known))}.'
            raise CampaignError(msg)
        values = tuple({axis: _axis_values(axis, value) for axis, value in grid.items()} for grid in grids)
        metrics = data.get('metrics', list(METRICS))
        if not isinstance(metrics, list):
            msg = f'metrics must be a list of names, like ["passing_time_s", "min_distance_m"]; got {metrics!r}.'
            raise CampaignError(msg)
        name = str(data.get('name', 'campaign'))
        out = None if data.get('out') is None else (base or Path()) / str(data['out'])
        confirm = _axis_values('seed', data['confirm_seeds']) if 'confirm_seeds' in data else ()
        held_out = data.get('held_out', False)
        if not isinstance(held_out, bool):
            raise CampaignError(f'held_out must be true or false; got {held_out!r}.')
        try:
            families = families_from_toml(data.get('families', {}))
        except FamilyError as err:
            raise CampaignError(str(err)) from err
        return cls(values, tuple(metrics), RunSettings(**settings), name, out, confirm, families, held_out, base)

    @property
    def judging(self) -> Judging:
        """How its report judges the claims: its families, and the confirm_seeds held out or pooled."""
        return Judging(self.families, self.confirm_seeds if self.held_out else ())

    @property
    def columns(self) -> list[str]:
        """The table's columns: the run's key, every axis, the metrics kept, wall time, the package's version, the
        scene file's sha256 (of its text), error."""
        return ['key', *AXES, *self.metrics, 'wall_s', 'version', 'scene_sha256', 'error']

    def scene_path(self, scene: str) -> str:
        """Where a scene of the grids is loaded from (`scene_from`)."""
        return scene_from(scene, self.base)

    def runnable(self, point: Point) -> Point:
        """``point`` with its scene where it is loaded from (`scene_path`), to run in any working directory."""
        return replace(point, scene=self.scene_path(point.scene))

    def points(self) -> list[Point]:
        """Every run, grid after grid, each grid in the order of AXES, with each scene's own N and saturation
        filled in; a run that two grids share is run once (`study.check_turns` refuses a scene first)."""
        points: dict[Point, None] = {}
        for grid in self.grids:
            for scene_name in grid['scene']:
                scene = load_scene(self.scene_path(scene_name))
                study.check_turns(scene, grid.get('model', ('paper',)))
                _ = [study.narrowed(scene, width) for width in grid.get('narrowest_m', ())]  # refused up front
                own = {'n_robots': (scene.swarm.n_robots,), 'saturation': (scene.control.saturation,)}
                axes = [grid.get(a) or own.get(a) or (getattr(Point, a),) for a in AXES if a != 'scene']
                axes[list(AXES).index('seed') - 1] += self.confirm_seeds
                for combination in itertools.product(*axes):
                    point = Point(scene_name, **dict(zip(list(AXES)[1:], combination, strict=True)))
                    if point.failure != 'none' and self.settings.failure_robot >= (point.n_robots or 0):
                        msg = (
                            f'settings.failure_robot = {self.settings.failure_robot} does not exist in a swarm of '
                            f'{point.n_robots} robots (scene {scene_name}); choose an index below {point.n_robots}.'
                        )
                        raise CampaignError(msg)
                    points[point] = None
        return list(points)

    def to_json(self) -> dict[str, Any]:
        """The campaign as recorded in ``campaign.json``."""
        return {
            'name': self.name,
            'grids': [{axis: list(values) for axis, values in grid.items()} for grid in self.grids],
            'metrics': list(self.metrics),
            'settings': asdict(self.settings),
        } | {key: value for key, value in self.judged_by().items() if value}

    def judged_by(self) -> dict[str, Any]:
        """The keys of `to_json` that say how the report judges, not what runs (REPORT_KEYS): a folder's runs
        stay its own when these change."""
        families = {f.name: f.to_json() for f in self.families}
        return {'confirm_seeds': list(self.confirm_seeds), 'held_out': self.held_out, 'families': families}


KEYS = ('name', 'out', 'axes', 'grids', 'metrics', 'settings', 'confirm_seeds', 'held_out', 'families')
"""The keys of a campaign file."""
REPORT_KEYS = ('held_out', 'families')
"""The keys that change the report, not the runs."""


LATER_AXES: dict[str, Any] = {'lag_s': 0.0, 'compensation': 'none', 'narrowest_m': 0.0}
LATER_AXES |= {'map': 'none', 'map_seed': 0, 'map_clutter': CLUTTER, 'map_width_m': WIDTH_M, 'controller': 'law'}
"""Axes added after campaigns were committed, with their defaults: a run at a default leaves them out of its key, so
that the tables written before keep their keys (a rerun resumes them)."""
LATER_COLUMNS = LATER_AXES | {'scene_sha256': ''}
"""Columns a table written before may lack, and what its rows hold there (no scene hash: not recorded then)."""


def run_key(point: Point, settings: RunSettings) -> str:
    """A run's stable key: a hash of its point and the campaign's settings (16 hex digits)."""
    fields = {k: v for k, v in asdict(point).items() if k not in LATER_AXES or v != LATER_AXES[k]}
    text = json.dumps({'point': fields, 'settings': asdict(settings)}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _axis_values(axis: str, value: Any) -> tuple[Any, ...]:
    """An axis's values from TOML: a list (for the runs' and the maps' seeds also a count n, for 0..n-1, or a text
    of `parse_seeds`, like "100-109"); scene files as named (relative to the campaign file: `scene_from`)."""
    if axis in ('seed', 'map_seed') and isinstance(value, str):
        try:
            return parse_seeds(value)
        except SeedsError as err:
            raise CampaignError(f'axes.{axis} = {value!r}: {err}') from err
    if axis in ('seed', 'map_seed') and isinstance(value, int) and not isinstance(value, bool):
        if value < 1:
            msg = f'axes.{axis} = {value} runs no seed; give a count >= 1 (seeds 0..n-1), a list or a range "10-19".'
            raise CampaignError(msg)
        return tuple(range(value))
    if not isinstance(value, list):
        msg = f'axes.{axis} must be a list of values, like {axis} = [{_example(axis)}]; got {value!r}.'
        raise CampaignError(msg)
    if axis == 'scene':  # a scene file as the campaign file names it, relative to it: the same from any directory
        return tuple(Path(v).as_posix() if isinstance(v, str) and v.endswith('.toml') else v for v in value)
    return tuple(value)


def scene_from(scene: str, base: Path | None) -> str:
    """Where the scene ``scene`` of a campaign whose file lies in ``base`` is loaded from: a shipped name or an
    absolute path as it is, a relative scene file from ``base``."""
    if base is None or not scene.endswith('.toml') or Path(scene).is_absolute():
        return scene
    return str(base / scene)


def _example(axis: str) -> str:
    kind = AXES.get(axis, str)
    return {int: '0, 1', float: '0.0, 0.02'}.get(kind, '"C", "D"' if axis == 'scene' else '"..."')


def _check_values(axis: str, values: Iterable[Any], base: Path | None = None) -> None:
    values = tuple(values)
    if not values:
        msg = f'axes.{axis} has no values, so the grid is empty; give at least one, like {axis} = [{_example(axis)}].'
        raise CampaignError(msg)
    kind = AXES[axis]
    for value in values:
        ok = isinstance(value, kind) and not isinstance(value, bool)
        if kind is float:
            ok = is_real(value)
        if not ok:
            msg = f'axes.{axis} holds {value!r}; its values must be {kind.__name__}s, like {axis} = [{_example(axis)}].'
            raise CampaignError(msg)
        if axis in _CHOICES and value not in _CHOICES[axis]:
            msg = f'axes.{axis} holds {value!r}; choose from {", ".join(map(repr, _CHOICES[axis]))}.'
            raise CampaignError(msg)
        low = {'n_robots': 1, 'seed': 0, 'latency_steps': 0, 'lag_s': 0.0, 'pose_noise_m': 0.0, 'dropout': 0.0}
        low |= {'map_seed': 0, 'map_clutter': 0, 'map_width_m': WIDTH_RANGE_M[0], 'narrowest_m': 0.0}
        high = {'dropout': 1.0, 'map_width_m': WIDTH_RANGE_M[1] + 1e-12}
        if axis in low and value < low[axis] or axis in high and value >= high[axis]:
            bounds = {'dropout': 'in [0, 1)', 'map_width_m': f'in [{WIDTH_RANGE_M[0]:g}, {WIDTH_RANGE_M[1]:g}] m'}
            bound = bounds.get(axis, f'>= {low.get(axis)}')
            msg = f'axes.{axis} holds {value!r}; its values must be {bound}.'
            raise CampaignError(msg)
        if axis == 'scene':
            load_scene(scene_from(value, base))  # a SceneError names the file and the fix


def _check_family(family: Family) -> None:
    """A family names comparisons of the campaign's modes ("a - b"), its metrics, and values of its axes."""
    for comparison in family.comparisons:
        modes = comparison.split(' - ')
        if len(modes) != 2 or any(m not in _CHOICES['mode'] for m in modes):
            msg = (
                f'families.{family.name}: {comparison!r} is not a comparison "a - b" of two modes, like '
                f'"planning - no planning"; the modes are {", ".join(map(repr, _CHOICES["mode"]))}.'
            )
            raise CampaignError(msg)
    wrong = [m for m in family.metrics if m not in METRICS]
    if wrong:
        raise CampaignError(f'families.{family.name}: unknown metric {wrong[0]!r}; choose from {", ".join(METRICS)}.')
    for axis, values in family.cells:
        if axis not in AXES or axis in ('seed', 'mode'):
            known = ', '.join(a for a in AXES if a not in ('seed', 'mode'))
            msg = f'families.{family.name}: unknown key {axis!r}; a family has comparisons, metrics and {known}.'
            raise CampaignError(msg)
        try:
            _check_values(axis, values)
        except CampaignError as err:
            raise CampaignError(f'families.{family.name}: {err}') from err


def _check_settings(settings: RunSettings) -> None:
    checks = (
        (
            is_real(settings.dt_s) and 1e-3 <= settings.dt_s <= 0.1,
            (
                'dt_s must be a number in [0.001, 0.1] (s; the studies fly 0.02): a coarser step jumps robots '
                'through each other and the walls, a finer one multiplies the run time'
            ),
        ),
        (is_real(settings.jitter_m) and settings.jitter_m >= 0, 'jitter_m must be a number >= 0 (m)'),
        (
            isinstance(settings.failure_robot, int)
            and not isinstance(settings.failure_robot, bool)
            and settings.failure_robot >= 0,
            'failure_robot must be a robot index >= 0',
        ),
        (is_real(settings.failure_at) and 0 <= settings.failure_at <= 1, 'failure_at must be in [0, 1] (of L)'),
    )
    for ok, text in checks:
        if not ok:
            msg = f'settings.{text}; got {asdict(settings)}.'
            raise CampaignError(msg)
