"""From a scene to a report, one stage at a time: plan, simulate, build, run, analyse.

Each stage writes its files and returns a typed record of what it did. The commands ``vtube plan``, ``simulate``,
``submission build`` and ``analyze`` are these stages; `demo` runs them in turn on the default Robotarium
scene, with the submission run in this process on the bundled simulator as the testbed would run it.
"""

from __future__ import annotations

import io
import os
import runpy
import traceback
from collections.abc import Callable, Iterator, Sequence
from contextlib import AbstractContextManager, contextmanager, redirect_stderr, redirect_stdout
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Literal

from robotarium_exp.analysis.loaders import load_trajectory
from robotarium_exp.analysis.metrics import Analysis
from robotarium_exp.analysis.recorded_tube import check_recorded_tube
from robotarium_exp.analysis.report import analyse, write_report
from robotarium_exp.analysis.trajectory import DEFAULT_MAX_GAP, MaxGap
from robotarium_exp.errors import AnalysisError
from robotarium_exp.fit import Fit, robotarium_fit
from robotarium_exp.rps_alias import install
from robotarium_exp.rps_import import kept_apart
from robotarium_exp.scene import load_scene
from submission.builder import Submission, build, build_declared, write
from submission.check import CheckReport
from submission.declaration import Declaration
from vtube.starts import GRID_START, started
from vtube_planning import plots
from vtube_planning.files import write_atomically
from vtube_planning.geometry.scene import Scene
from vtube_planning.log import LogWriter
from vtube_planning.params import SwarmParams
from vtube_planning.planning.plan import Plan
from vtube_planning.planning.planner import plan_convex
from vtube_planning.provenance import copy_scene, provenance
from vtube_planning.swarm.foresight import with_foresight
from vtube_planning.swarm.simulate import SimConfig, SimResult, simulate

PlanMethod = Literal['convex', 'polynomial']
Tick = Callable[[float], None]
"""Told how far a long stage has come (simulated seconds, frames written)."""
Progress = Callable[[str, str], AbstractContextManager[Tick]]
"""Opens the display of a long stage's progress (what, unit) and gives its tick."""

DEMO_SCENE = 'robotarium_curve'


@contextmanager
def no_progress(what: str, unit: str) -> Iterator[Tick]:
    """Progress shown nowhere."""
    yield lambda value: None


def plan_for(scene: Scene, swarm: SwarmParams | None = None, plan_file: Path | None = None) -> Plan:
    """The plan read from ``plan_file`` (refused unless it was made for this scene and swarm), else a new one."""
    swarm = swarm or scene.swarm
    if plan_file is None:
        return plan_convex(scene.tube, swarm, scene.planning, scene=scene.name)
    loaded = Plan.load(plan_file, scene.tube)
    loaded.check_matches(scene.tube, swarm, scene.planning, scene=scene.name)
    return loaded


@dataclass(frozen=True)
class Planned:
    """A scene's plan (its provenance recorded), the files written (the plan, its figure, the scene's copy) and,
    for a scene declared for the Robotarium, whether it fits there."""

    scene: Scene
    plan: Plan
    method: PlanMethod
    plan_file: Path
    figure: Path
    scene_copy: Path
    fit: Fit | None = None


def plan_scene(
    name_or_path: str | Path,
    out: Path,
    *,
    method: PlanMethod = 'convex',
    grid_step_m: float | None = None,
    objective: str | None = None,
) -> Planned:
    """Plan speed and density for a scene (its grid and objective, or ``grid_step_m``, ``objective``); write
    ``plan_<scene>.npz``, its figure and the scene's copy to ``out``."""
    scene = load_scene(name_or_path)
    options = scene.planning if grid_step_m is None else replace(scene.planning, grid_step_m=grid_step_m)
    options = options if objective is None else replace(options, objective=objective)
    solve: Callable[..., Plan] = plan_convex
    if method == 'polynomial':  # the paper's cubics, posed in cvxpy (imported here: about half a second)
        from vtube_planning.planning.polynomial import plan_polynomial as solve
    plan = solve(scene.tube, scene.swarm, options, scene=scene.name)
    plan = replace(plan, provenance=provenance(scene=scene))
    plan_file = plan.save(out / f'plan_{scene.name}.npz')
    figure = plots.save_figure(plots.plan_figure(plan), out / f'plan_{scene.name}.png')
    fit = robotarium_fit(scene) if scene.testbed == 'robotarium' else None
    return Planned(scene, plan, method, plan_file, figure, copy_scene(scene, out), fit)


@dataclass(frozen=True)
class Simulated:
    """A simulated passage of ``swarm`` through ``scene`` with ``config``, and the files written: the log, the
    figures, the GIF when asked for, the scene's copy."""

    scene: Scene
    swarm: SwarmParams
    config: SimConfig
    result: SimResult
    written: tuple[Path, ...]
    start: str = GRID_START
    """Where the robots started, in words."""

    @property
    def log(self) -> Path:
        return self.written[0]


class SimulationInterrupted(KeyboardInterrupt):
    """Ctrl-C during a simulation; its text says where the steps flown so far are."""


def simulate_scene(
    name_or_path: str | Path,
    out: Path,
    *,
    planning: bool = True,
    n_robots: int | None = None,
    plan_file: Path | None = None,
    config: SimConfig | None = None,
    foresight: bool = False,
    animate: bool = False,
    progress: Progress = no_progress,
) -> Simulated:
    """Fly the scene's swarm (of ``n_robots``, default the scene's) through its tube, with its plan (from
    ``plan_file``, or planned here) or without; write the log, figures, a GIF when asked for and the scene's copy
    to ``out``. Unless ``config`` says where the robots start, a Robotarium scene's start where its flight's do
    (`robotarium_start`). ``foresight``: the law flies under the foresight (`with_foresight`)."""
    scene = load_scene(name_or_path)
    scene = replace(scene, control=with_foresight(scene.control, scene.swarm)) if foresight else scene
    swarm = scene.swarm if n_robots is None else replace(scene.swarm, n_robots=n_robots)
    plan = plan_for(scene, swarm, plan_file) if planning else None
    config, start = started(scene, swarm, config or SimConfig())
    mode = 'planned' if planning else 'unplanned'
    stem, log = out / f'sim_{scene.name}_{mode}', out / f'sim_{scene.name}_{mode}.npz'
    made = provenance(scene=scene, plan_file=plan_file, seeds=[config.seed])
    try:
        with progress('simulated', 's') as tick:
            result = simulate(
                scene.tube,
                swarm,
                scene.control,
                plan=plan,
                config=config,
                on_step=tick,
                log_path=log,
                meta={'scene': scene.name, 'source': scene.source, 'provenance': made},
            )
    except KeyboardInterrupt:
        partial = LogWriter(log, {}).partial_path
        kept = f'the steps flown so far are in {partial}' if partial and partial.exists() else 'nothing was flown yet'
        raise SimulationInterrupted(f'interrupted: {kept}; a finished log at {log} is left as it was.') from None
    written = [
        log,
        plots.save_figure(plots.snapshots_figure(result, scene.tube), f'{stem}_snapshots.png'),
        plots.save_figure(plots.distance_figure({mode: result}), f'{stem}_distance.png'),
    ]
    if plan is not None:
        written.append(plots.save_figure(plots.tracking_figure(result, plan), f'{stem}_tracking.png'))
    if animate:
        with progress('GIF frames', 'frame') as tick:
            written.append(plots.animate(result, scene.tube, f'{stem}.gif', progress=lambda i, n: tick(i + 1)))
    written.append(copy_scene(scene, out))
    return Simulated(scene, swarm, config, result, tuple(written), start)


@dataclass(frozen=True)
class WrittenSubmission:
    """A submission written to ``path`` and its preflight (None: not checked)."""

    submission: Submission
    path: Path
    report: CheckReport | None

    @property
    def declaration(self) -> Declaration | None:
        """The duration the header records (None: it records none)."""
        if self.report is None or not self.report.passed:
            return None
        return self.report.declaration


def build_submission(
    name_or_path: str | Path,
    out: Path,
    *,
    planning: bool = True,
    plan_file: Path | None = None,
    declare: bool = True,
    seeds: int | Sequence[int] = 3,
    initializer_seeds: int = 200,
    testbed_models: tuple[str, ...] | None = None,
    margin_seeds: Sequence[int] = (),
    progress: Callable[[str], None] | None = None,
    seed_done: Callable[[], None] | None = None,
) -> WrittenSubmission:
    """Write the single-file submission for a Robotarium scene (its plan from ``plan_file``, or planned here) to
    ``out``; with ``declare``, preflighted under ``testbed_models`` (None: every model of
    `submission.robustness.CHECKED_MODELS`; with ``margin_seeds``, the delay margin too) and rewritten with the
    duration to declare
    (`submission.builder.build_declared`: one build, one preflight, which reports to ``progress`` and
    ``seed_done``)."""
    scene = load_scene(name_or_path)
    plan = plan_for(scene, plan_file=plan_file) if planning else None
    if not declare:
        submission = build(scene, plan, plan_file=plan_file)
        return WrittenSubmission(submission, write(submission, out), None)
    from submission.robustness import CHECKED_MODELS

    models = CHECKED_MODELS if testbed_models is None else testbed_models
    submission, report, written = build_declared(
        scene,
        plan,
        out,
        seeds=seeds,
        initializer_seeds=initializer_seeds,
        testbed_models=models,
        margin_seeds=margin_seeds,
        progress=progress,
        seed_done=seed_done,
        plan_file=plan_file,
    )
    return WrittenSubmission(submission, written, report)


@dataclass(frozen=True)
class Returned:
    """A submission run as the testbed would: the folder it saved its files in, the log of what it printed, and
    whether it ended without an error."""

    folder: Path
    log: Path
    ok: bool


def run_on_bundled(script: Path, folder: Path, *, seed: int = 0) -> Returned:
    """Run a submission file in this process on the bundled V2 simulator (``rps`` resolved to ours, ``random`` and
    ``np.random`` seeded with ``seed``, no figure) in ``folder``, where it saves its files; what it prints goes to
    ``folder/log.txt``."""
    script = script.resolve()
    folder.mkdir(parents=True, exist_ok=True)
    printed, complained = io.StringIO(), io.StringIO()
    ok = True
    with _as_on_the_testbed(folder, seed), redirect_stdout(printed), redirect_stderr(complained):
        try:
            runpy.run_path(str(script), run_name='__main__')
        except SystemExit as stop:
            ok = stop.code in (None, 0)
        except Exception:  # noqa: BLE001 -- the script's error is its run's outcome, told in its log
            traceback.print_exc()
            ok = False
    log = folder / 'log.txt'
    write_atomically(log, printed.getvalue() + complained.getvalue())
    return Returned(folder, log, ok)


@contextmanager
def _as_on_the_testbed(folder: Path, seed: int) -> Iterator[None]:
    """Inside: ``import rps`` is the bundled V2 simulator (`robotarium_exp.rps_alias.install`), the working
    folder is ``folder`` and the submission runs headless; all three are restored after, and so are cvxopt's options
    (`robotarium_exp.rps_import.kept_apart`)."""
    cwd, headless = Path.cwd(), os.environ.get('VTUBE_HEADLESS')
    with kept_apart():
        install(seed=seed)
        os.environ['VTUBE_HEADLESS'] = '1'
        os.chdir(folder)
        try:
            yield
        finally:
            os.chdir(cwd)
            if headless is None:
                del os.environ['VTUBE_HEADLESS']
            else:
                os.environ['VTUBE_HEADLESS'] = headless


@dataclass(frozen=True)
class AnalysisOptions:
    """How data is read and measured: in a scene (None: no tube metrics), against a plan file (needs the scene),
    beside a log (``compare``); the bags' topics and frames, the world frame, the longest gap interpolated (text:
    ``3periods``, ``0.25s``) and the distance counted as a collision (default: the scene's 2 r_p)."""

    scene: str | None = None
    plan_file: Path | None = None
    compare: Path | None = None
    topic_pattern: str | None = None
    frame_pattern: str | None = None
    topics: tuple[str, ...] | None = None
    world_frame: str | None = None
    max_gap: str | None = None
    collision_distance_m: float | None = None


@dataclass(frozen=True)
class Analysed:
    """Data measured (``data``; ``comparison``: the log shown beside it) and the report and metrics written."""

    scene: Scene | None
    data: Analysis
    comparison: Analysis | None
    report: Path
    metrics_file: Path


def analyse_data(inputs: Sequence[Path], out: Path, options: AnalysisOptions | None = None) -> Analysed:
    """Measure returned or recorded data (testbed folder, .mat file, our logs, ROS bags); write metrics, report,
    figures and the scene's copy to ``out``."""
    options = options or AnalysisOptions()
    if options.plan_file is not None and options.scene is None:
        raise AnalysisError('a plan file needs the scene it was made for; give the scene too.')
    scene = load_scene(options.scene) if options.scene is not None else None
    plan = plan_for(scene, plan_file=options.plan_file) if scene is not None and options.plan_file else None
    gap = MaxGap.parse(options.max_gap) if options.max_gap is not None else DEFAULT_MAX_GAP
    topics = list(options.topics) if options.topics is not None else None
    bags = {'topic_pattern': options.topic_pattern, 'frame_pattern': options.frame_pattern, 'topics': topics}
    recorded = {
        'scene': options.scene,
        'plan': str(options.plan_file) if options.plan_file else None,
        'max_gap': str(gap),
        'collision_distance_m': options.collision_distance_m,
        'world_frame': options.world_frame,
        **bags,
    }
    trajectory = load_trajectory(list(inputs), max_gap=gap, world_frame=options.world_frame, **bags)
    if scene is not None:
        check_recorded_tube(trajectory, scene)
    distance = options.collision_distance_m
    results = {'data': analyse(trajectory, scene, plan, collision_distance_m=distance, options=recorded)}
    if options.compare is not None:
        simulated = load_trajectory([options.compare], max_gap=gap)
        if scene is not None:  # the log shown beside the data is measured in the same tube
            check_recorded_tube(simulated, scene)
        if scene is not None:  # the log shown beside the data is measured in the same tube
            check_recorded_tube(simulated, scene)
        results['comparison'] = analyse(simulated, scene, plan, collision_distance_m=distance)
    report = write_report(out, results, scene, plan)
    if scene is not None:
        copy_scene(scene, out)
    return Analysed(scene, results['data'], results.get('comparison'), report, out / 'metrics.json')


DemoStage = Planned | Simulated | WrittenSubmission | Returned | Analysed


def demo(out: Path, *, progress: Progress = no_progress) -> Iterator[DemoStage]:
    """The whole way on `DEMO_SCENE` with the bundled simulator, into ``out``: plan; simulate with the plan
    and without; build and check the submission; run it as the testbed would; analyse what it returns beside the
    planned simulation. Yields each stage's result as it ends and stops after a submission that records no
    declaration or a run that failed."""
    planned = plan_scene(DEMO_SCENE, out / 'plan')
    yield planned
    flown = simulate_scene(DEMO_SCENE, out / 'simulation', plan_file=planned.plan_file, progress=progress)
    yield flown
    yield simulate_scene(DEMO_SCENE, out / 'simulation', planning=False, progress=progress)
    path = out / 'submission' / 'experiment.py'
    built = build_submission(DEMO_SCENE, path, plan_file=planned.plan_file, seeds=2, initializer_seeds=20)
    yield built
    if built.declaration is None:
        return
    returned = run_on_bundled(built.path, out / 'returned')
    yield returned
    if not returned.ok:
        return
    options = AnalysisOptions(scene=DEMO_SCENE, plan_file=planned.plan_file, compare=flown.log)
    yield analyse_data([returned.folder], out / 'report', options)
