"""The paper's comparison: the same swarm through scenes A-D with and without planning, over several seeds.

For every scene and seed the swarm flies once with the plan (planned speed, r_a following (a3)) and once without
(constant mid-range speed, constant r_a), from the same jittered initial formation. The paper's claim, checked
per scene on the means over seeds and per seed: with planning the passing time is shorter, the minimum distance
larger, and no two robots collide. With ``baselines``, scenes C and D also fly the paper's baselines (optimized
flocking with v_min = 0 as the paper ran it and a speed-constrained variant; distributed NMPC), compared on safety:
the paper's claim is that the planned method passes more safely (fewer collisions, larger minimum distance).

The ablation grid (:func:`iter_grid`, ``vtube ablation``) says where that comes from: modes that each switch one part
of the method off on the same code path (ABLATIONS), over swarm sizes, seeds, robot models and saturations, one
tidy row per run; :func:`grid_markdown` reports each cell with bootstrap intervals and the paired differences of
COMPARISONS (:mod:`vtube_planning.stats`). The paper's comparison above is a slice of it (:func:`run_study`).
"""

from __future__ import annotations

import csv
import math
import multiprocessing
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vtube_planning.baselines.flocking import FlockingParams, flocking_command
from vtube_planning.baselines.nmpc import NmpcParams, NmpcSwarm
from vtube_planning.geometry.scene import Scene, load_scene
from vtube_planning.params import SwarmParams
from vtube_planning.planning.plan import Plan
from vtube_planning.planning.planner import plan_convex
from vtube_planning.stats import Estimate, cell_values, mean_interval, paired_difference, verdict
from vtube_planning.swarm.control import ControlParams
from vtube_planning.swarm.metrics import tracking_errors
from vtube_planning.swarm.simulate import SimConfig, SimResult, default_constant_speed, simulate

MODES = ('planning', 'no planning')
BASELINE_MODES = ('flocking', 'flocking (v_min)', 'nmpc')
BASELINE_SCENES = ('C', 'D')


def run_study(
    scenes: Iterable[str],
    seeds: Iterable[int],
    *,
    config: SimConfig | None = None,
    progress: Callable[[str], None] | None = None,
    baselines: Iterable[str] = (),
) -> list[dict[str, Any]]:
    """One row per scene, mode and seed with the passage's metrics; ``baselines`` from BASELINE_MODES.

    The paper's comparison as a slice of the ablation grid (:func:`iter_grid`): the scenes' own swarm, the robot
    model of ``config``, the modes 'planning' and 'no planning', and the baselines on scenes C and D.
    """
    config = config or SimConfig()
    model = 'acceleration limits' if config.acceleration_limits else 'paper'
    rows = []
    for name in scenes:
        modes = MODES + (tuple(baselines) if load_scene(name).name in BASELINE_SCENES else ())
        for row in iter_grid([name], None, seeds, modes=modes, models=[model], config=config):
            rows.append(row)
            if progress is not None:
                progress(row_text(row))
    return rows


def _baseline_setup(mode: str, scene: Scene, swarm: SwarmParams, dt_s: float) -> Setup:
    """A baseline's swarm law as the simulator's ``baseline`` hook (positions, velocities, projection), and for
    NMPC its solver, whose convergence the grid reports."""
    if mode == 'nmpc':
        nmpc = NmpcSwarm(scene.tube, NmpcParams.for_swarm(swarm))
        law = lambda positions, velocities, projection: nmpc.command(positions, velocities, projection, dt_s)
        return Setup(None, scene.control, None, law, nmpc)
    params = FlockingParams.scaled(swarm, speed_constrained=mode == 'flocking (v_min)')
    law = lambda positions, velocities, projection: flocking_command(positions, velocities, projection, params)
    return Setup(None, scene.control, None, law)


def summarise(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per scene: means and ranges per mode, and whether the paper's claims hold (on means and per seed)."""
    out = []
    for name in dict.fromkeys(r['scene'] for r in rows):
        entry: dict[str, Any] = {'scene': name}
        per_mode = {}
        modes = list(dict.fromkeys(r['mode'] for r in rows if r['scene'] == name))
        entry['modes'] = modes
        for mode in modes:
            sel = [r for r in rows if r['scene'] == name and r['mode'] == mode]
            passing = np.array([r['passing_time_s'] for r in sel])
            distance = np.array([r['min_distance_m'] for r in sel])
            per_mode[mode] = sel
            entry[mode] = {
                'passing_time_s': float(passing.mean()),
                'passing_time_range_s': [float(passing.min()), float(passing.max())],
                'min_distance_m': float(distance.mean()),
                'min_distance_range_m': [float(distance.min()), float(distance.max())],
                'collision_pairs': int(sum(r['collision_pairs'] for r in sel)),
                'incursion_depth_m': float(max(r['incursion_depth_m'] for r in sel)),
                'nmpc_converged_share': float(np.mean([r['nmpc_converged_share'] for r in sel])),
                'tube_violation_steps': int(sum(r['tube_violation_steps'] for r in sel)),
                'completed': all(r['completed'] for r in sel),
            }
        planned, unplanned = entry['planning'], entry['no planning']
        entry['claim_on_means'] = (
            planned['passing_time_s'] < unplanned['passing_time_s']
            and planned['min_distance_m'] > unplanned['min_distance_m']
            and planned['collision_pairs'] == 0
        )
        pairs = zip(per_mode['planning'], per_mode['no planning'], strict=True)
        entry['claim_per_seed'] = [
            {
                'seed': p['seed'],
                'holds': p['passing_time_s'] < u['passing_time_s']
                and p['min_distance_m'] > u['min_distance_m']
                and p['collision_pairs'] == 0,
            }
            for p, u in pairs
        ]
        entry['safer_than'] = {
            mode: planned['collision_pairs'] < entry[mode]['collision_pairs']
            or (
                planned['collision_pairs'] == entry[mode]['collision_pairs'] == 0
                and planned['min_distance_m'] > entry[mode]['min_distance_m']
            )
            for mode in modes
            if mode in BASELINE_MODES
        }
        out.append(entry)
    return out


def study_markdown(summary: list[dict[str, Any]], seeds: list[int], config: SimConfig) -> str:
    """The comparison as a Markdown table, with the claim's verdict per scene."""
    model = 'with the acceleration limits (3), (4) per robot' if config.acceleration_limits else "the paper's model"
    lines = [
        (
            f'Scenes with and without planning, Table 1 swarm (N = 20), {model}, dt = {config.dt_s} s, '
            f'seeds {seeds[0]}..{seeds[-1]} (initial jitter {config.jitter_m} m). Means over seeds, [min, max].'
        ),
        '',
        (
            '| scene | mode | passing time [s] | min distance [m] | collisions (pairs) | deepest incursion [m] '
            '| tube violations (robot-steps) |'
        ),
        '|---|---|---|---|---|---|---|',
    ]
    for entry in summary:
        for mode in entry['modes']:
            e = entry[mode]
            lo, hi = e['passing_time_range_s']
            dlo, dhi = e['min_distance_range_m']
            lines.append(
                f'| {entry["scene"]} | {mode} | {e["passing_time_s"]:.2f} [{lo:.2f}, {hi:.2f}] | '
                f'{e["min_distance_m"]:.3f} [{dlo:.3f}, {dhi:.3f}] | {e["collision_pairs"]} | '
                f'{e["incursion_depth_m"]:.3f} | {e["tube_violation_steps"]} |'
            )
    lines += ['', "The paper's claim (with planning: shorter passing time, larger minimum distance, no collision):", '']
    for entry in summary:
        held = [c['seed'] for c in entry['claim_per_seed'] if c['holds']]
        failed = [c['seed'] for c in entry['claim_per_seed'] if not c['holds']]
        verdict = 'holds' if entry['claim_on_means'] else 'does not hold'
        detail = f'; per seed it holds for {len(held)} of {len(held) + len(failed)}'
        if failed:
            detail += f' (not for seed {", ".join(map(str, failed))})'
        lines.append(f'- scene {entry["scene"]}: {verdict} on the means{detail}.')
    compared = [entry for entry in summary if entry['safer_than']]
    if compared:
        lines += [
            '',
            (
                'Against the baselines (planning safer: fewer collisions, or none on either side and a '
                'larger minimum distance):'
            ),
            '',
        ]
        for entry in compared:
            for mode, safer in entry['safer_than'].items():
                lines.append(
                    f'- scene {entry["scene"]}, {mode}: {"holds" if safer else "does not hold"} '
                    f'({entry["planning"]["collision_pairs"]} against {entry[mode]["collision_pairs"]} '
                    'collision pairs).'
                )
        solved = [entry for entry in compared if 'nmpc' in entry['modes']]
        if solved:
            lines += ['', "NMPC's solves (IPOPT, every agent every 0.1 s) that converged, mean over seeds:", '']
            lines += [f'- scene {e["scene"]}: {e["nmpc"]["nmpc_converged_share"]:.1%}.' for e in solved]
    return '\n'.join(lines) + '\n'


# ---------------------------------------------------------------------- the ablation grid


@dataclass(frozen=True)
class Ablation:
    """Which parts of the method a mode keeps, all flown by the same simulator and swarm step.

    ``plan``: the plan flown, ``'full'``, ``'without (p7)'`` (planned with ``predictive_model = 'none'``), ``'flat'``
    (the full plan's grid with the constant speed and density rho_d: (a3) then tracks a flat rho_d) or ``'none'``
    (constant speed, constant r_a); ``a3``: whether r_a follows (a3) (off: its gain and feed-forward are zero);
    ``speed``: the constant forward speed of ``'flat'`` and ``'none'``, ``'mid'`` = (v_min + v_max) / 2 or
    ``'v_max'``.
    """

    plan: str
    a3: bool
    speed: str = 'mid'


ABLATIONS = {
    'planning': Ablation('full', a3=True),
    'planning without (p7)': Ablation('without (p7)', a3=True),
    'planned speed, (a3) off': Ablation('full', a3=False),
    'constant speed, (a3) to rho_d': Ablation('flat', a3=True),
    'no planning': Ablation('none', a3=False),
    'no planning at v_max': Ablation('none', a3=False, speed='v_max'),
}
MODELS = {'paper': False, 'acceleration limits': True}
"""Robot models: the paper's p' = sat(v_c), or every robot also held to the acceleration limits (3), (4)."""
GRID_SCENES = ('C', 'D')
"""The scenes whose plans pre-expand (p7 binds before the narrowing); on A and B the plan is the same without it."""


@dataclass(frozen=True)
class Setup:
    """What one mode hands the simulator: the plan (or None), the control parameters, the constant speed."""

    plan: Plan | None
    control: ControlParams
    constant_speed_mps: float | None
    baseline: Callable[..., Any] | None = None
    nmpc: NmpcSwarm | None = None


def ablation_setup(
    mode: str, scene: Scene, swarm: SwarmParams, plans: dict[tuple[str, int, str], Plan], dt_s: float
) -> Setup:
    """The simulator's inputs for ``mode`` (a key of ABLATIONS, or of BASELINE_MODES); ``plans`` caches the plans
    by scene, N and (p7)."""
    if mode in BASELINE_MODES:
        return _baseline_setup(mode, scene, swarm, dt_s)
    ablation = ABLATIONS[mode]
    speed = default_constant_speed(swarm) if ablation.speed == 'mid' else swarm.v_max_mps
    control = scene.control if ablation.a3 else replace(scene.control, k_ra_m3ps=0.0, feedforward=False)
    if ablation.plan == 'none':
        return Setup(None, control, speed)
    model = 'none' if ablation.plan == 'without (p7)' else scene.planning.predictive_model
    plan = _cached_plan(scene, swarm, plans, model)
    if ablation.plan == 'flat':
        plan = replace(
            plan,
            speed_mps=np.full_like(plan.speed_mps, speed),
            density_per_m2=np.full_like(plan.density_per_m2, swarm.rho_d_per_m2),
            method='flat: constant speed, density rho_d',
        )
    return Setup(plan, control, None)


def _cached_plan(scene: Scene, swarm: SwarmParams, plans: dict[tuple[str, int, str], Plan], model: str) -> Plan:
    """The scene's plan for this swarm with (p7) read as ``model``, planned once per scene, N and model."""
    key = (scene.name, swarm.n_robots, model)
    if key not in plans:
        plans[key] = plan_convex(scene.tube, swarm, replace(scene.planning, predictive_model=model), scene=scene.name)
    return plans[key]


def iter_grid(
    scenes: Iterable[str] = GRID_SCENES,
    sizes: Iterable[int] | None = (20, 40, 80),
    seeds: Iterable[int] = range(10),
    *,
    modes: Iterable[str] = tuple(ABLATIONS),
    models: Iterable[str] = tuple(MODELS),
    saturations: Iterable[str] | None = None,
    config: SimConfig | None = None,
    workers: int = 1,
) -> Iterator[dict[str, Any]]:
    """The ablation grid: one tidy row per scene, mode, swarm size N (None: the scene's own), seed and robot model,
    yielded as the runs finish.

    Besides the passage's metrics a row holds the density error against the *full* plan's rho* (the same reference
    for every mode: mean |rho - rho*(l_c)| while the swarm's centre is in the tube) and the share of in-tube
    robot-steps moving backwards along the tube. ``saturations`` (``SATURATIONS``; None: the scene's own) is how
    the command meets the speed band. ``workers`` processes share the runs (one task: every mode of one scene, N,
    model, saturation and seed); the rows are the same, in the same order, for any number.
    """
    config = config or SimConfig()
    modes = tuple(modes)
    tasks = []
    for name in scenes:
        scene = load_scene(name)
        for n in sizes or (scene.swarm.n_robots,):
            for model in models:
                for saturation in saturations or (scene.control.saturation,):
                    tasks += [(name, int(n), model, saturation, seed, modes, config) for seed in seeds]
    if workers <= 1:
        for task in tasks:
            yield from _grid_task(*task)
        return
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context('spawn')) as pool:
        for task_rows in pool.map(_grid_task, *zip(*tasks, strict=True)):
            yield from task_rows


def row_text(row: dict[str, Any]) -> str:
    """One grid row in a line."""
    where = f'{row["scene"]} N={row["n_robots"]} {row["model"]} {row["saturation"]} sat seed {row["seed"]}'
    return (
        f'{where} {row["mode"]}: passing {row["passing_time_s"]:.2f} s, min distance {row["min_distance_m"]:.3f} m, '
        f'collisions {row["collision_pairs"]}'
    )


def _grid_task(
    name: str, n: int, model: str, saturation: str, seed: int, modes: tuple[str, ...], config: SimConfig
) -> list[dict[str, Any]]:
    """Every mode of one scene, swarm size, robot model, saturation and seed."""
    scene = load_scene(name)
    scene = replace(scene, control=replace(scene.control, saturation=saturation))
    swarm = replace(scene.swarm, n_robots=n)
    plans: dict[tuple[str, int, str], Plan] = {}
    reference = _cached_plan(scene, swarm, plans, scene.planning.predictive_model)  # the full plan
    rows = []
    for mode in modes:
        setup = ablation_setup(mode, scene, swarm, plans, config.dt_s)
        result = simulate(
            scene.tube,
            swarm,
            setup.control,
            plan=setup.plan,
            config=replace(config, seed=seed, acceleration_limits=MODELS[model]),
            constant_speed_mps=setup.constant_speed_mps,
            baseline=setup.baseline,
        )
        row = {'scene': scene.name, 'mode': mode, 'n_robots': n, 'seed': seed, 'model': model, 'saturation': saturation}
        row.update(_grid_metrics(result, reference, scene.tube.length_m))
        row['nmpc_converged_share'] = setup.nmpc.converged_share if setup.nmpc is not None else math.nan
        rows.append(row)
    return rows


def _grid_metrics(result: SimResult, reference: Plan, length_m: float) -> dict[str, Any]:
    m = result.metrics
    tracking = tracking_errors(result.l_m, result.forward_speed_mps, result.density_per_m2, reference, length_m)
    in_tube = (result.l_m >= 0.0) & (result.l_m <= length_m)
    backwards = (result.forward_speed_mps < 0.0) & in_tube
    return {
        'passing_time_s': m.passing_time_s,
        'min_distance_m': m.min_distance_m,
        'collision_pairs': m.collision_pairs,
        'incursion_depth_m': max(0.0, m.collision_distance_m - m.min_distance_m),
        'tube_violation_steps': m.tube_violation_steps,
        'completed': m.completed,
        'density_error_per_m2': tracking.get('density_tracking_mean_per_m2', math.nan),
        'reversing_share': float(backwards.sum() / max(1, in_tube.sum())),
    }


COMPARISONS = (
    ('planning', 'no planning', "the paper's comparison"),
    ('planning', 'no planning at v_max', 'the plan against the fastest constant speed'),
    ('planning', 'planning without (p7)', 'what the pre-expansion (p7) buys'),
    ('planning', 'planned speed, (a3) off', 'what (a3) buys on top of the planned speed'),
    ('constant speed, (a3) to rho_d', 'no planning', 'what (a3) buys without a plan'),
)
"""Paired comparisons of the grid report: mode a against mode b on the same seeds, and what the difference means."""
CLAIMS = (('passing_time_s', 'lower', 'passing time [s]'), ('min_distance_m', 'higher', 'min distance [m]'))


def verdict_summary(rows: list[dict[str, Any]]) -> str:
    """Where each comparison's claim holds: per robot model and saturation, in how many cells (scene, N) the paired
    interval says a beats b (+), cannot tell (=) or b beats a (-), for each metric of CLAIMS."""
    table = paired_table(rows)
    settings = list(dict.fromkeys((p['model'], p['saturation']) for p in table))
    head = ' | '.join(f'{model} model, {sat} sat' for model, sat in settings)
    lines = [
        (
            'Cells (scene, N) where a beats b (+), the interval includes zero (=), or b beats a (-); '
            'T: passing time (shorter is better), D: minimum distance (larger is better).'
        ),
        '',
        f'| comparison (a - b) | {head} |',
        '|---|' + '---|' * len(settings),
    ]
    for a, b, meaning in COMPARISONS:
        cols = []
        for model, sat in settings:
            counts = []
            for (metric, _, _), letter in zip(CLAIMS, 'TD', strict=True):
                found = [
                    p['verdict']
                    for p in table
                    if (p['a'], p['b'], p['model'], p['saturation'], p['metric']) == (a, b, model, sat, metric)
                ]
                plus, same, minus = (found.count(v) for v in ('holds', 'does not hold', 'reversed'))
                counts.append(f'{letter} +{plus} ={same} -{minus}')
            cols.append(', '.join(counts))
        lines.append(f'| {a} - {b} ({meaning}) | ' + ' | '.join(cols) + ' |')
    return '\n'.join(lines) + '\n'


def mode_summary(rows: list[dict[str, Any]]) -> str:
    """Per mode and setting (robot model, saturation), over every scene, N and seed: collision pairs, the runs
    with any, and the range over cells of the share of robot-steps moving backwards."""
    settings = list(dict.fromkeys((r['model'], r['saturation']) for r in rows))
    lines = [
        (
            'Per mode over all cells and seeds: collision pairs (runs with any / runs); share of in-tube robot-steps '
            'moving backwards, lowest and highest cell mean.'
        ),
        '',
        '| mode | ' + ' | '.join(f'{m} model, {s} sat' for m, s in settings) + ' |',
        '|---|' + '---|' * len(settings),
    ]
    for mode in dict.fromkeys(r['mode'] for r in rows):
        cols = []
        for model, sat in settings:
            sel = [r for r in rows if (r['mode'], r['model'], r['saturation']) == (mode, model, sat)]
            cells = dict.fromkeys((r['scene'], r['n_robots']) for r in sel)
            backwards = [
                np.mean([r['reversing_share'] for r in sel if (r['scene'], r['n_robots']) == c]) for c in cells
            ]
            hit = sum(r['collision_pairs'] > 0 for r in sel)
            pairs = sum(r['collision_pairs'] for r in sel)
            cols.append(f'{pairs} ({hit}/{len(sel)}); {min(backwards):.1%}-{max(backwards):.1%}')
        lines.append(f'| {mode} | ' + ' | '.join(cols) + ' |')
    return '\n'.join(lines) + '\n'


def grid_markdown(rows: list[dict[str, Any]]) -> str:
    """The grid's report: where each comparison holds (:func:`verdict_summary`), then per scene, N, model and
    saturation each mode's means with 95 % bootstrap intervals and the paired differences of COMPARISONS with their
    intervals and verdicts (a claim holds only where the interval excludes zero)."""
    lines: list[str] = [verdict_summary(rows), mode_summary(rows)]
    for cell in dict.fromkeys(_cell(r) for r in rows):
        scene, n, model, saturation = cell
        sel = [r for r in rows if _cell(r) == cell]
        modes = list(dict.fromkeys(r['mode'] for r in sel))
        seeds = sorted({r['seed'] for r in sel})
        lines += [
            f'### Scene {scene}, N = {n}, {model} model, {saturation} sat ({len(seeds)} seeds)',
            '',
            (
                '| mode | passing time [s] | min distance [m] | 5 % min distance [m] | collisions (pairs, all seeds) '
                '| tube violations (robot-steps, mean) | density error [1/m^2] | reversing robot-steps |'
            ),
            '|---|---|---|---|---|---|---|---|',
        ]
        for mode in modes:
            values = {k: cell_values(sel, k, mode=mode) for k in ('passing_time_s', 'min_distance_m')}
            extra = {k: cell_values(sel, k, mode=mode) for k in ('density_error_per_m2', 'reversing_share')}
            collisions = int(cell_values(sel, 'collision_pairs', mode=mode).sum())
            lines.append(
                f'| {mode} | {_interval(values["passing_time_s"], 2)} | {_interval(values["min_distance_m"], 3)} | '
                f'{_quantile(values["min_distance_m"])} | {collisions} | '
                f'{np.mean(cell_values(sel, "tube_violation_steps", mode=mode)):.0f} | '
                f'{_interval(extra["density_error_per_m2"], 3)} '
                f'| {np.mean(extra["reversing_share"]):.1%} |'
            )
        lines += [
            '',
            '| comparison (a - b, same seeds) | ' + ' | '.join(t for _, _, t in CLAIMS) + ' |',
            '|---|---|---|',
        ]
        differences = paired_table(sel)
        for a, b, meaning in COMPARISONS:
            if a not in modes or b not in modes:
                continue
            found = {p['metric']: p for p in differences if (p['a'], p['b']) == (a, b)}
            cols = [
                f'{found[m]["estimate"].text(3)}: {found[m]["verdict"]}' if m in found else 'n/a' for m, _, _ in CLAIMS
            ]
            lines.append(f'| {a} - {b} ({meaning}) | ' + ' | '.join(cols) + ' |')
        lines.append('')
    return '\n'.join(lines)


def paired_table(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per scene, N and model, the paired differences of COMPARISONS on each metric of CLAIMS: dicts with scene,
    n_robots, model, a, b, metric, estimate (an :class:`~vtube_planning.stats.Estimate`) and verdict. Comparisons
    whose modes are missing, or whose runs did not all complete, are left out."""
    out = []
    for cell in dict.fromkeys(_cell(r) for r in rows):
        scene, n, model, saturation = cell
        sel = [r for r in rows if _cell(r) == cell]
        for a, b, _ in COMPARISONS:
            for metric, better, _ in CLAIMS:
                diff = _paired(cell_values(sel, metric, mode=a), cell_values(sel, metric, mode=b))
                if diff is not None:
                    fields = {'scene': scene, 'n_robots': n, 'model': model, 'saturation': saturation}
                    fields |= {'a': a, 'b': b, 'metric': metric}
                    out.append(fields | {'estimate': diff, 'verdict': verdict(diff, better)})
    return out


def _cell(row: dict[str, Any]) -> tuple[str, int, str, str]:
    """What a row's mode is compared within: scene, N, robot model and saturation."""
    return row['scene'], row['n_robots'], row['model'], row['saturation']


def _interval(values: NDArray[np.float64], digits: int) -> str:
    finite = values[np.isfinite(values)]
    if finite.size < values.size:
        return f'{finite.size} of {values.size} completed'
    return mean_interval(values).text(digits) if values.size > 1 else f'{values[0]:.{digits}f}'


def _quantile(values: NDArray[np.float64]) -> str:
    return f'{np.quantile(values, 0.05):.3f}' if values.size else 'n/a'


def _paired(a: NDArray[np.float64], b: NDArray[np.float64]) -> Estimate | None:
    if a.size < 2 or a.size != b.size or not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        return None
    return paired_difference(a, b)


class RowWriter:
    """The tidy table as CSV, one line per run appended and flushed as it comes, so that an interrupted grid leaves
    a readable file with every finished run; the columns are the first row's."""

    def __init__(self, path: Path) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        self.path = path
        self._handle = path.open('w', newline='', encoding='utf-8')
        self._writer: csv.DictWriter[str] | None = None

    def write(self, row: dict[str, Any]) -> None:
        if self._writer is None:
            self._writer = csv.DictWriter(self._handle, fieldnames=list(row))
            self._writer.writeheader()
        self._writer.writerow(row)
        self._handle.flush()

    def close(self) -> None:
        self._handle.close()


def read_rows_csv(path: Path) -> list[dict[str, Any]]:
    """Rows written by :class:`RowWriter`, with numbers and booleans typed again."""
    with path.open(newline='', encoding='utf-8') as handle:
        return [{k: _typed(v) for k, v in row.items()} for row in csv.DictReader(handle)]


def _typed(text: str) -> Any:
    if text in ('True', 'False'):
        return text == 'True'
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text
