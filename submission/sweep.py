"""The acceptance sweep of one's own Robotarium experiments (``vtube robotarium sweep``): scenes x robot counts.

For each scene and robot count N (a *case*), the scene is loaded with N robots and asked whether it fits the
Robotarium (`robotarium_exp.fit.robotarium_fit`, asked to prove a start formation's refusal physical where Oler's
bound does not): a scene that does not is a *refused* row with the verdict's one-line reason. Otherwise it is planned (an uncertified plan is a FAIL row), built without the declaration
step ([`submission.builder.build`][submission.builder.build]), and the file is run on the bundled simulator with V2's
initialization for the seeds asked (0..seeds-1 for a count) exactly as the preflight runs it
(`submission.check.run_file`). Each run is measured from the poses and commands the simulator itself validated
(`measure_run`) and the case is judged against the bar of issue 31 (`judge`): the preflight's verdict on every run (no
verifier count, simulator's or recounted, the run ended normally, every robot past the exit), every robot parked in its
slot, no robot-step with the body on the wall, and a mean density error in the plan's dip at most `DIP_ERROR_BAR`.

The cases run in parallel (`vtube_planning.studies.executors.map_unordered`), each row appended to ``runs.csv`` as
it comes (`vtube_planning.studies.campaign_store.prepare_table`: a rerun does only the missing rows; a case that
raised is a row with its error, done again next time); ``sweep.md`` holds the table, scene x N.
"""

from __future__ import annotations

import csv
import hashlib
import math
import re
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.errors import RobotariumExpError
from robotarium_exp.fit import robotarium_fit
from robotarium_exp.flight_data import FlightData
from robotarium_exp.scene import load_scene
from robotarium_exp.tracking import plan_tracking
from submission.builder import build, write
from submission.check import RUN_TIMEOUT_S, RunReport, file_flight_data, run_file
from submission.errors import SubmissionError
from submission.robustness import record_passage
from vtube_planning import __version__
from vtube_planning.errors import VtubeError
from vtube_planning.files import write_atomically
from vtube_planning.geometry.from_maps.map_file import generated_scene, is_map_file
from vtube_planning.geometry.scene import Scene
from vtube_planning.onboard import swarm_area
from vtube_planning.onboard.parking import PARKED_WITHIN_M
from vtube_planning.planning.plan import Plan
from vtube_planning.planning.planner import plan_convex
from vtube_planning.studies.campaign_store import RUNS_FILE, holding, prepare_table
from vtube_planning.studies.executors import map_unordered
from vtube_planning.studies.seeds import seeds_text

DIP_ERROR_BAR = 0.25
"""The largest mean relative density error |rho - rho*| / rho* over the plan's dip that passes (issue 31)."""
SWEEP_FILE, TABLE_FILE, FILES_FOLDER, TUBES_FOLDER = 'sweep.json', 'sweep.md', 'files', 'tubes'
MEASURES = (
    'too_close',
    'outside',
    'actuator',
    'through',
    'parked',
    'body_on_wall',
    'dip_error',
    'passing_time_s',
    'min_distance_m',
)
COLUMNS = ['key', 'scene', 'n_robots', 'status', 'reason', *MEASURES, 'error', 'wall_s', 'version']


@dataclass(frozen=True)
class Case:
    """One row of the sweep: a scene (shipped name or .toml path) with ``n_robots``, flown for ``seeds``; the built
    file goes to ``folder``."""

    scene: str
    n_robots: int
    seeds: tuple[int, ...]
    folder: Path
    run_timeout_s: float = RUN_TIMEOUT_S


@dataclass(frozen=True)
class RunMeasures:
    """One run of a built file, measured from what the simulator validated (`measure_run`).

    ``problems`` are the preflight's ([`submission.check.RunReport.problems`][submission.check.RunReport.problems]:
    crash, verifier counts, a robot not past the exit, a body on a wall); ``through``: every robot past the exit; ``parked``: every
    robot's control point in its own slot at the end; ``body_on_wall``: robot-steps with 0 <= l <= L and the body (not
    only the centre) touching or crossing the wall; ``dip_error``: the mean |rho - rho*| / rho* over the plan's dip
    (None: no dip flown).
    """

    label: str
    problems: tuple[str, ...]
    too_close: int
    outside: int
    actuator: int
    through: bool
    parked: bool = False
    body_on_wall: int = 0
    dip_error: float | None = None
    passing_time_s: float | None = None
    min_distance_m: float | None = None


def measure_run(run: RunReport, data: FlightData, scene: Scene, plan: Plan) -> RunMeasures:
    """The measures of one preflight run of a file built from ``scene`` and ``plan`` (``data``: its flight data)."""
    record, counted, recounted = run.record, run.counted, run.recounted
    if record is None or counted is None or recounted is None or record.poses.shape[0] < 2:
        return RunMeasures(run.label, tuple(run.problems) or ('left no steps',), 0, 0, 0, through=False)
    poses, tube, n = record.poses, scene.tube, record.poses.shape[2]
    metrics, t_s, l_m = record_passage(record, tube, 2.0 * scene.swarm.r_p_m)
    arrays = {
        't_s': t_s,
        'l_m': l_m,
        'dxu': record.commands,
        'density_per_m2': n / swarm_area(tube, l_m.min(axis=1), l_m.max(axis=1), scene.swarm.r_a_m),
        'flying': ~np.maximum.accumulate(l_m > tube.length_m, axis=0),  # exited robots park: the swarm's end
    }
    return RunMeasures(
        run.label,
        tuple(run.problems),
        max(counted.too_close, recounted.too_close),  # the worse of the simulator's count and the recount
        max(counted.outside, recounted.outside),
        max(counted.actuator, recounted.actuator),
        through=run.completed,
        parked=parked_at_end(poses[-1], record.commands[-1], record.dt_s, data),
        body_on_wall=metrics.tube_violation_steps,
        dip_error=plan_tracking(arrays, plan, scene).dip.density_error_mean,
        passing_time_s=None if math.isnan(metrics.passing_time_s) else metrics.passing_time_s,
        min_distance_m=metrics.min_distance_m,
    )


def parked_at_end(pose: np.ndarray, command: np.ndarray, dt_s: float, data: FlightData) -> bool:
    """Whether every robot's control point ends in its own parking slot (within the flight's tolerance), after the
    last recorded step: ``pose`` (3, N) moved by its ``command`` [v; omega] (2, N) for ``dt_s``."""
    heading = pose[2] + command[1] * dt_s
    centre = pose[:2] + command[0] * dt_s * np.array([np.cos(pose[2]), np.sin(pose[2])])
    points = centre + data.projection_distance_m * np.array([np.cos(heading), np.sin(heading)])
    gaps = np.hypot(*(data.parking_slots[:, :, None] - points[:, None, :]))  # (slots, robots)
    nearest = gaps.argmin(axis=0)
    within = gaps.min(axis=0) < PARKED_WITHIN_M
    return bool(within.all()) and len(set(nearest.tolist())) == nearest.size


def judge(runs: Sequence[RunMeasures]) -> tuple[str, str]:
    """PASS, or FAIL with every criterion that failed (named, with the first run that failed it)."""
    failed: dict[str, str] = {}
    for run in runs:
        found = [*run.problems]
        found += ['not every robot parked in its slot'] * (run.through and not run.parked)  # else: not through
        if run.dip_error is not None and run.dip_error > DIP_ERROR_BAR:
            found.append(f'density error in the dip {100 * run.dip_error:.0f} % > {100 * DIP_ERROR_BAR:.0f} %')
        for problem in found:
            failed.setdefault(re.sub(r'[0-9.]+', '#', problem), f'{run.label}: {problem}')  # each criterion once
    return ('FAIL', '; '.join(failed.values())) if failed or not runs else ('PASS', '')


def case_row(case: Case) -> dict[str, Any]:
    """The row of one case (module docstring); raised errors other than the build's refusal propagate."""
    scene = load_scene(case.scene, n_robots=case.n_robots)
    fit = robotarium_fit(scene, prove=True)
    if not fit.fits:
        return {'status': 'refused', 'reason': fit.reason}
    try:
        plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    except VtubeError as err:
        return {'status': 'FAIL', 'reason': f'no plan: {err}'}
    if not plan.is_certified():
        return {'status': 'FAIL', 'reason': f'plan not certified (worst violation {plan.max_violation:.2g})'}
    try:
        submission = build(scene, plan)
    except (SubmissionError, RobotariumExpError, VtubeError) as err:
        return {'status': 'FAIL', 'reason': f'the verdict said it fits, but the build refused: {err}'}
    path = write(submission, case.folder / f'{scene.name}_n{case.n_robots}.py')
    data = file_flight_data(submission.source)
    runs = [
        measure_run(run_file(path, 'bundled', seed, data, case.run_timeout_s), data, scene, plan) for seed in case.seeds
    ]
    status, reason = judge(runs)
    return {'status': status, 'reason': reason, **summarise(runs)}


def summarise(runs: Sequence[RunMeasures]) -> dict[str, Any]:
    """The row's measures over the runs: counts summed, booleans all, the worst dip error, passing time and
    distance (empty where no run measured them)."""
    dips = [r.dip_error for r in runs if r.dip_error is not None]
    times = [r.passing_time_s for r in runs if r.passing_time_s is not None]
    distances = [r.min_distance_m for r in runs if r.min_distance_m is not None]
    return {
        'too_close': sum(r.too_close for r in runs),
        'outside': sum(r.outside for r in runs),
        'actuator': sum(r.actuator for r in runs),
        'through': all(r.through for r in runs),
        'parked': all(r.parked for r in runs),
        'body_on_wall': sum(r.body_on_wall for r in runs),
        'dip_error': round(max(dips), 4) if dips else '',
        'passing_time_s': round(max(times), 2) if times and len(times) == len(runs) else '',
        'min_distance_m': round(min(distances), 4) if distances else '',
    }


def _execute(case: Case) -> dict[str, Any]:
    """One case in a worker: its row, wall time and version; a case that raises gives its error instead."""
    started = time.perf_counter()
    try:
        row = case_row(case) | {'error': ''}
    except Exception as err:  # noqa: BLE001 - recorded in the table; the other cases go on
        row = {'status': 'error', 'error': f'{type(err).__name__}: {" ".join(str(err).split())}'}
    return row | {'wall_s': round(time.perf_counter() - started, 3), 'version': __version__}


@dataclass(frozen=True)
class SweepOutcome:
    """Every case's row in the grid's order (scene, then N), how many were done before and now, the seconds it
    took, and the files: ``runs.csv`` and ``sweep.md``."""

    rows: list[dict[str, Any]]
    skipped: int
    ran: int
    seconds: float
    table: Path
    markdown: Path

    @property
    def failed(self) -> list[dict[str, Any]]:
        """The rows that failed the bar or raised (a refusal with its reason is not a failure)."""
        return [row for row in self.rows if row['status'] in ('FAIL', 'error')]


def scene_label(scene: str) -> str:
    """A scene's name in the table: a file's stem, or the shipped name."""
    return Path(scene).stem if scene.endswith('.toml') else scene


def case_key(case: Case) -> str:
    """A stable key of a case: its scene's content (a file's text, or a shipped name), N and the seeds."""
    path = Path(case.scene)
    scene = path.read_text(encoding='utf-8') if path.suffix == '.toml' and path.is_file() else case.scene
    return hashlib.sha256(f'{scene}\n{case.n_robots}\n{_seeds_key(case.seeds)}'.encode()).hexdigest()[:16]


def _seeds_key(seeds: tuple[int, ...]) -> int | str:
    """The seeds as keys and the record hold them: seeds 0..n-1 as the count n (as before ranges were taken, so
    that earlier sweeps resume), others as their text (`vtube_planning.studies.seeds.seeds_text`)."""
    return len(seeds) if seeds == tuple(range(len(seeds))) else seeds_text(seeds)


def sweep(
    scenes: Sequence[str],
    sizes: Sequence[int],
    out: Path,
    *,
    seeds: int | Sequence[int] = 3,
    jobs: int = 1,
    run_timeout_s: float = RUN_TIMEOUT_S,
    on_row: Callable[[dict[str, Any]], None] | None = None,
) -> SweepOutcome:
    """Run every case of ``scenes`` x ``sizes`` not yet in ``out/runs.csv`` on ``jobs`` local processes, appending
    each row as it comes (``on_row`` sees it), and write ``out/sweep.md``; built files go to ``out/files``, the
    scenes generated from map files to ``out/tubes`` (`flown_scene`).
    ``seeds``: the seeds each case flies, or a count n for 0..n-1."""
    started = time.perf_counter()
    flown = tuple(range(seeds)) if isinstance(seeds, int) else tuple(seeds)
    record = {'kind': 'robotarium sweep', 'scenes': list(scenes), 'n_robots': list(sizes), 'seeds': _seeds_key(flown)}
    with holding(out, 'sweep'):
        tubes = [flown_scene(scene, out / TUBES_FOLDER) for scene in scenes]
        cases = [Case(s, n, flown, out / FILES_FOLDER, run_timeout_s) for s in tubes for n in sizes]
        keys = [case_key(case) for case in cases]
        expected = {key: {'version': __version__} for key in keys}  # rows of another version: refused
        rows = prepare_table(out, SWEEP_FILE, record, COLUMNS, expected, what='sweep')
        todo = [k for k, key in enumerate(keys) if key not in rows]
        with (out / RUNS_FILE).open('a', newline='', encoding='utf-8') as handle:
            writer = csv.DictWriter(handle, fieldnames=COLUMNS)
            for i, measured in map_unordered(_execute, [cases[k] for k in todo], workers=jobs):
                case, key = cases[todo[i]], keys[todo[i]]
                head = {'key': key, 'scene': scene_label(case.scene), 'n_robots': case.n_robots, 'reason': ''}
                row = head | dict.fromkeys(MEASURES, '') | measured
                writer.writerow(row)
                handle.flush()
                rows[key] = row
                if on_row is not None:
                    on_row(row)
    ordered = [rows[key] for key in keys]
    markdown = out / TABLE_FILE
    write_atomically(markdown, sweep_markdown(ordered, flown))
    seconds = time.perf_counter() - started
    return SweepOutcome(ordered, len(keys) - len(todo), len(todo), seconds, out / RUNS_FILE, markdown)


def flown_scene(scene: str, folder: Path) -> str:
    """``scene`` as the sweep flies it: a map file (a scene file with [tube.generate]) generated into ``folder``
    under its own name, as `vtube tube generate` writes it (the tube its rows were flown in, kept beside them); a
    shipped name or a scene file as it is."""
    path = Path(scene)
    text = path.read_text(encoding='utf-8') if path.suffix == '.toml' and path.is_file() else ''
    if not is_map_file(text):
        return scene
    generated, _ = generated_scene(text, scene, folder)
    target = folder / path.name
    write_atomically(target, generated)
    return str(target)


def sweep_markdown(rows: Sequence[dict[str, Any]], seeds: Sequence[int]) -> str:
    """The table scene x N (PASS, FAIL [k], refused [k], error [k]: reason k listed below it), then every row."""
    scenes = list(dict.fromkeys(str(row['scene']) for row in rows))
    sizes = sorted({int(row['n_robots']) for row in rows})
    reasons: list[str] = []
    cells: dict[tuple[str, int], str] = {}
    for row in rows:
        reason = str(row['error'] or row['reason'])
        if reason:
            reasons.append(f'{row["scene"]}, N = {row["n_robots"]}: {reason}')
        cells[str(row['scene']), int(row['n_robots'])] = f'{row["status"]} [{len(reasons)}]' * bool(reason) or str(
            row['status']
        )
    lines = [
        '# Robotarium sweep',
        '',
        (
            f"Each case: built without declaration, run on the bundled simulator with V2's initialization, seeds "
            f'{seeds_text(seeds)}. PASS: no verifier count, every robot through and parked, no body on the wall, density '
            f'error in the dip <= {100 * DIP_ERROR_BAR:.0f} %, in every run.'
        ),
        '',
        '| scene | ' + ' | '.join(f'N = {n}' for n in sizes) + ' |',
        '|---|' + '---|' * len(sizes),
        *(f'| {s} | ' + ' | '.join(cells.get((s, n), '') for n in sizes) + ' |' for s in scenes),
        '',
        *(f'{k}. {reason}' for k, reason in enumerate(reasons, start=1)),
        *[''] * bool(reasons),
        (
            '| scene | N | status | too close | outside | actuator | through | parked | body on wall | dip error | '
            'passing time [s] | min distance [m] | wall [s] |'
        ),
        '|---' * 13 + '|',
        *(_row_line(row) for row in rows),
    ]
    return '\n'.join(lines) + '\n'


def _row_line(row: dict[str, Any]) -> str:
    dip = row['dip_error']
    cells = [row['scene'], row['n_robots'], row['status'], *(row[m] for m in MEASURES[:6])]
    cells += [f'{100 * float(dip):.1f} %' if dip != '' else '', row['passing_time_s'], row['min_distance_m']]
    return '| ' + ' | '.join(str(cell) for cell in [*cells, row['wall_s']]) + ' |'
