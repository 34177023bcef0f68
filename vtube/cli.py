"""The ``vtube`` command line.

Every command is a plain function returning an exit code: 0 on success, 2 on bad input (after printing one
``error: ...`` line to stderr, never a traceback).
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from robotarium_exp.errors import RobotariumExpError
from robotarium_exp.rps.errors import RobotariumError
from unicycle_mapping.errors import MappingError
from vtube_planning.errors import VtubeError

if TYPE_CHECKING:
    from submission.check import CheckReport
    from vtube_planning.campaign import Campaign, Outcome
    from vtube_planning.geometry.scene import Scene
    from vtube_planning.params import SwarmParams
    from vtube_planning.planning.plan import Plan

EXIT_OK = 0
EXIT_BAD_INPUT = 2
EXIT_INTERRUPTED = 130


def scene_list() -> int:
    """Print the shipped scenes, one per line: name, length, title."""
    from vtube_planning.geometry.scene import list_scenes, load_scene

    for name in list_scenes():
        scene = load_scene(name)
        print(f'{name:<22} {scene.tube.length_m:7.2f} m  {scene.title}')
    return EXIT_OK


def scene_show(name_or_path: str, out: Path | None) -> int:
    """Load a scene (shipped name or .toml file), print its summary, and draw it to ``out`` when given."""
    from vtube_planning.geometry.scene import load_scene

    if out is not None:
        _figure_path(out)
    scene = load_scene(name_or_path)
    summary = scene.tube.summary()
    swarm = scene.swarm
    print(f'scene {scene.name}: {scene.title}')
    source = scene.source
    if source.startswith('<shipped>'):
        source += f'  (vtube scene export {scene.name} FILE.toml writes a copy to edit)'
    print(f'  source                {source}')
    print(f'  length                {summary["length_m"]:.3f} m')
    print(f'  half-width            {summary["half_width_min_m"]:.3f} .. {summary["half_width_max_m"]:.3f} m')
    print(f'  min curvature radius  {summary["curvature_radius_min_m"]:.3f} m')
    print(f'  max lambda |kappa|    {summary["lambda_kappa_max"]:.3f}  (regular below 1)')
    print(f'  area                  {summary["area_m2"]:.3f} m^2')
    print(
        f'  swarm                 N = {swarm.n_robots}, v in [{swarm.v_min_mps:g}, {swarm.v_max_mps:g}] m/s, '
        f'r_p/r_s/r_a = {swarm.r_p_m:g}/{swarm.r_s_m:g}/{swarm.r_a_m:g} m, rho_d = {swarm.rho_d_per_m2:g}, '
        f'rho_max = {swarm.rho_max_per_m2:g} /m^2, a_rho = {swarm.a_rho:.4g} /m^2/s'
    )
    if out is not None:
        from vtube_planning.plots import save_figure, scene_figure

        path = save_figure(scene_figure(scene), out)
        print(f'  figure                {path}')
    return EXIT_OK


def scene_export(name: str, path: Path) -> int:
    """Write a shipped scene's TOML file to ``path``, to edit and use as a scene of one's own."""
    from vtube_planning.geometry.scene import shipped_scene_text

    spelled, text = shipped_scene_text(name)
    if path.exists():
        print(f'error: {path} exists; give another file name (nothing was written).', file=sys.stderr)
        return EXIT_BAD_INPUT
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding='utf-8')
    print(f'scene {spelled} written to {path}; edit it and pass the file where a scene is asked for')
    return EXIT_OK


def plan(
    name_or_path: str,
    out: Path,
    method: str = 'convex',
    grid_step_m: float | None = None,
    json_out: dict[str, Any] | None = None,
) -> int:
    """Plan speed and density for a scene; print the summary, write ``plan_<scene>.npz`` and its figure to ``out``
    (``json_out``, when given, receives the result for ``--json``)."""
    from dataclasses import replace

    from vtube_planning.geometry.scene import load_scene
    from vtube_planning.planning.planner import plan_convex
    from vtube_planning.planning.polynomial import plan_polynomial
    from vtube_planning.plots import plan_figure, save_figure
    from vtube_planning.provenance import copy_scene, provenance

    scene = load_scene(name_or_path)
    options = scene.planning if grid_step_m is None else replace(scene.planning, grid_step_m=grid_step_m)
    solve = {'convex': plan_convex, 'polynomial': plan_polynomial}[method]
    result = solve(scene.tube, scene.swarm, options, scene=scene.name)
    print(
        f'plan for scene {scene.name} ({method}, {result.l_m.size} grid points, {result.status} after '
        f'{result.iterations} iterations, {result.solve_time_s:.3f} s)'
    )
    print(f'  traversal time        {result.time_s:.4f} s')
    print(
        f'  objective J           {result.objective["total"]:.6f}  (time {result.objective["time_s"]:.6f} + '
        f'density {result.objective["density"]:.6f})'
    )
    print(f'  speed                 {result.speed_mps.min():.4g} .. {result.speed_mps.max():.4g} m/s')
    k = int(result.density_per_m2.argmin())
    print(
        f'  density               min {result.density_per_m2[k]:.4g} at l = {result.l_m[k]:.3f} m, '
        f'rho_d = {scene.swarm.rho_d_per_m2:g} /m^2'
    )
    worst = ', '.join(f'{name} {value:.1e}' for name, value in result.certificate.items())
    verdict = 'certified' if result.is_certified() else 'NOT certified (violation above 1e-6)'
    print(f'  certificate           {verdict}: {worst}')
    result = replace(result, extra=result.extra | {'provenance': provenance(scene=scene)})
    plan_path = result.save(out / f'plan_{scene.name}.npz')
    figure_path = save_figure(plan_figure(result), out / f'plan_{scene.name}.png')
    print(f'  written               {plan_path}, {figure_path}, {copy_scene(scene, out)}')
    if json_out is not None:
        json_out |= {'plan_file': str(plan_path), 'time_s': result.time_s, 'objective': result.objective}
        json_out |= {'certificate': result.certificate, 'certified': result.is_certified()}
        json_out |= {'provenance': result.extra['provenance']}
    return EXIT_OK


def _plan_for(scene: Scene, swarm: SwarmParams | None = None, plan_path: Path | None = None) -> Plan:
    """The plan read from ``plan_path`` (refused unless it was made for this scene and swarm), else a new one."""
    from vtube_planning.planning.plan import Plan
    from vtube_planning.planning.planner import plan_convex

    swarm = swarm or scene.swarm
    if plan_path is None:
        return plan_convex(scene.tube, swarm, scene.planning, scene=scene.name)
    loaded = Plan.load(plan_path)
    loaded.check_matches(scene.tube, swarm, scene.planning, scene=scene.name)
    return loaded


def simulate(
    name_or_path: str,
    out: Path,
    *,
    planning: bool = True,
    n_robots: int | None = None,
    seed: int = 0,
    acceleration_limits: bool = False,
    animate: bool = False,
    plan_path: Path | None = None,
    replan_every_s: float = 0.0,
    json_out: dict[str, Any] | None = None,
    quiet: bool = False,
) -> int:
    """Fly the scene's swarm through its tube; print the metrics, write the log, figures and (optionally) a GIF
    (``json_out``, when given, receives the metrics for ``--json``)."""
    from dataclasses import replace

    from vtube_planning import plots
    from vtube_planning.geometry.scene import load_scene
    from vtube_planning.provenance import copy_scene, provenance
    from vtube_planning.swarm.simulate import SimConfig
    from vtube_planning.swarm.simulate import simulate as run

    scene = load_scene(name_or_path)
    swarm = scene.swarm if n_robots is None else replace(scene.swarm, n_robots=n_robots)
    plan = _plan_for(scene, swarm, plan_path) if planning else None
    mode = 'planned' if planning else 'unplanned'
    config = SimConfig(seed=seed, acceleration_limits=acceleration_limits, replan_every_s=replan_every_s)
    log = out / f'sim_{scene.name}_{mode}.npz'
    bar = _progress_bar('simulated', 's', quiet)
    try:
        with bar:
            result = run(
                scene.tube,
                swarm,
                scene.control,
                plan=plan,
                config=config,
                on_step=lambda t: bar.update(t - bar.n),
                log_path=log,
                meta={
                    'scene': scene.name,
                    'source': scene.source,
                    'provenance': provenance(scene=scene, plan_file=plan_path, seeds=[seed]),
                },
            )
    except KeyboardInterrupt:
        partial = log.with_name(f'{log.stem}.partial{log.suffix}')
        kept = f'the steps flown so far are in {partial}' if partial.exists() else 'nothing was flown yet'
        print(f'interrupted: {kept}; a finished log at {log} is left as it was.', file=sys.stderr)
        return EXIT_INTERRUPTED
    m = result.metrics
    print(
        f'simulation of scene {scene.name} {"with" if planning else "without"} planning: N = {swarm.n_robots}, '
        f'seed {seed}, {result.t_s.size} steps of {config.dt_s} s'
    )
    rows = [
        ('passing time', f'{m.passing_time_s:.3f} s' + ('' if m.completed else ' (not every robot exited)')),
        ('minimum distance', f'{m.min_distance_m:.4f} m at t = {m.min_distance_time_s:.2f} s'),
        ('collisions', f'{m.collision_pairs} pairs closer than 2 r_p = {m.collision_distance_m:g} m'),
        (
            'tube violations',
            (f'{m.tube_violation_steps} robot-steps, {m.robots_outside} robots, up to {m.max_outside_m:.3f} m outside'),
        ),
        ('speed violations', f'{m.speed_violations} commands outside [v_min, v_max]'),
    ]
    if m.speed_tracking_mean_mps is not None:
        rows += [
            ('speed tracking', f'mean {m.speed_tracking_mean_mps:.3f}, max {m.speed_tracking_max_mps:.3f} m/s'),
            (
                'density tracking',
                (f'mean {m.density_tracking_mean_per_m2:.4f}, max {m.density_tracking_max_per_m2:.4f} /m^2'),
            ),
        ]
    replans = result.meta.get('replans')
    if replans is not None:
        done = sorted(call['wall_ms'] for call in replans if not call['error'])
        timing = f', median {done[len(done) // 2]:.0f} ms, largest {done[-1]:.0f} ms' if done else ''
        infeasible = len(replans) - len(done)
        summary = f'every {replan_every_s:g} s: {len(done)} replans{timing}; {infeasible} found the state infeasible'
        rows.append(('replanning', f'{summary} and kept the plan'))
    for name, value in rows:
        print(f'  {name:<18} {value}')
    stem = out / f'sim_{scene.name}_{mode}'
    written = [
        log,
        plots.save_figure(plots.snapshots_figure(result, scene.tube), f'{stem}_snapshots.png'),
        plots.save_figure(plots.distance_figure({mode: result}), f'{stem}_distance.png'),
    ]
    if plan is not None:
        written.append(plots.save_figure(plots.tracking_figure(result, plan), f'{stem}_tracking.png'))
    if animate:
        with _progress_bar('GIF frames', 'frame', quiet) as frames:
            written.append(plots.animate(result, scene.tube, f'{stem}.gif', progress=lambda i, n: frames.update()))
    written.append(copy_scene(scene, out))
    print(f'  {"written":<18} {", ".join(map(str, written))}')
    if json_out is not None:
        json_out |= {'log': str(log), 'metrics': m.to_json(), 'provenance': result.meta['provenance']}
        if replans is not None:
            json_out['replans'] = replans
    return EXIT_OK


def study(
    out: Path,
    *,
    scenes: Sequence[str],
    seeds: int,
    acceleration_limits: bool = False,
    baselines: bool = False,
    execution: Execution | None = None,
) -> int:
    """The paper's comparison with and without planning, as a campaign in ``out`` (runs.csv, campaign.json; a
    rerun resumes it); writes study.md, study.json and study.png."""
    import json

    from vtube_planning import plots
    from vtube_planning.campaign import Campaign
    from vtube_planning.params import SwarmParams
    from vtube_planning.study import BASELINE_MODES, BASELINE_SCENES, MODES, study_markdown, summarise
    from vtube_planning.swarm.metrics import strict_json

    common = {'seed': tuple(range(seeds)), 'model': ('acceleration limits' if acceleration_limits else 'paper',)}
    grids = [common | {'scene': tuple(scenes), 'mode': MODES}]
    compared = tuple(s for s in scenes if s in BASELINE_SCENES)
    if baselines and compared:
        grids.append(common | {'scene': compared, 'mode': MODES + BASELINE_MODES})
    outcome = _run_campaign(Campaign(tuple(grids), name='study'), out, execution or Execution())
    if outcome is None:
        return EXIT_INTERRUPTED
    rows = [row for row in outcome.rows if not row['error']]
    summary = summarise(rows)
    text = study_markdown(summary, list(range(seeds)), acceleration_limits)
    (out / 'study.md').write_text(text, encoding='utf-8')
    (out / 'study.json').write_text(
        json.dumps(strict_json({'rows': rows, 'summary': summary}), indent=1, allow_nan=False), encoding='utf-8'
    )
    figure = plots.save_figure(plots.study_figure(summary, 2 * SwarmParams().r_p_m), out / 'study.png')
    print()
    print(text)
    print(f'written {out / "study.md"}, {out / "study.json"}, {figure}')
    return EXIT_OK if all(e['claim_on_means'] for e in summary) and not outcome.failed else 1


def ablation(
    out: Path,
    *,
    scenes: Sequence[str],
    sizes: Sequence[int],
    seeds: int,
    models: Sequence[str],
    saturations: Sequence[str],
    execution: Execution | None = None,
) -> int:
    """The ablation grid as a campaign in ``out`` (a rerun resumes it), and its report."""
    from vtube_planning.campaign import Campaign
    from vtube_planning.study import ABLATIONS

    grid = {'scene': tuple(scenes), 'n_robots': tuple(sizes), 'seed': tuple(range(seeds)), 'model': tuple(models)}
    grid |= {'saturation': tuple(saturations), 'mode': tuple(ABLATIONS)}
    return campaign_run(Campaign((grid,), name='ablation'), out, execution)


@dataclass(frozen=True)
class Execution:
    """Where a campaign's runs go: ``workers`` local processes (0: one per core), or the Dask scheduler at
    ``scheduler`` (answering within ``timeout_s``); ``quiet``: no progress bar."""

    workers: int = 0
    scheduler: str | None = None
    timeout_s: float = 10.0
    quiet: bool = False


def campaign_run(campaign: Campaign | Path, out: Path | None, execution: Execution | None = None) -> int:
    """Run a campaign (a TOML file, or built by a command) into ``out``, resuming it, then write its report; exit 1
    when a run failed (its error is in the table; a rerun tries it again)."""
    from vtube_planning.campaign import Campaign

    if isinstance(campaign, Path):
        campaign = Campaign.from_toml(campaign)
    out = out or campaign.out
    if out is None:
        msg = 'give the output folder: --out DIR, or out = "DIR" in the campaign file.'
        raise VtubeError(msg)
    outcome = _run_campaign(campaign, out, execution or Execution())
    if outcome is None:
        return EXIT_INTERRUPTED
    return max(campaign_report(out), 1 if outcome.failed else EXIT_OK)


def _run_campaign(campaign: Campaign, out: Path, execution: Execution) -> Outcome | None:
    """Run what is missing of the campaign (None if interrupted): checks the folder and connects to the scheduler
    before any run, and prints one line of what was done and one per failed run."""
    import os

    from vtube_planning.campaign import RUNS_FILE, run_campaign
    from vtube_planning.executors import connect

    _writable_folder(out)
    points = campaign.points()  # a bad scene fails here, before any run
    client = connect(execution.scheduler, execution.timeout_s) if execution.scheduler else None
    workers = execution.workers or os.cpu_count() or 1
    where = f'{workers} local process' + ('es' if workers > 1 else '')
    if client is not None:
        where = f'the Dask cluster at {execution.scheduler}'
    try:
        outcome = run_campaign(
            campaign, out, workers=workers, client=client, progress=False if execution.quiet else None
        )
    except KeyboardInterrupt:
        print(
            f'interrupted: every finished run is in {out / RUNS_FILE}; run the same command again to do the rest.',
            file=sys.stderr,
        )
        return None
    finally:
        if client is not None:
            client.close()
    print(
        f'{campaign.name}: {len(points)} runs, {outcome.skipped} already done, {outcome.ran} run now on {where} '
        f'in {outcome.seconds:.0f} s, {outcome.failed} failed; table {out / RUNS_FILE}'
    )
    for row in outcome.rows:
        if row['error']:
            print(f'  failed: {row["key"]} ({row["scene"]}, {row["mode"]}, seed {row["seed"]}): {row["error"]}')
    return outcome


def campaign_report(out: Path) -> int:
    """A campaign folder's tables and figures (report.md, differences.png, means.png), from its table alone."""
    from vtube_planning import plots
    from vtube_planning.campaign import read_results
    from vtube_planning.study import grid_markdown

    campaign, rows, missing = read_results(out)
    if not rows:
        print(f'error: {out} holds no finished run yet; run the campaign first.', file=sys.stderr)
        return EXIT_BAD_INPUT
    head = f'Campaign {campaign.name!r}: {len(rows)} runs'
    if missing:
        head += f' ({missing} of the grid missing or failed: the tables are partial; rerun the campaign to finish)'
    text = f'{head}.\n\n' + grid_markdown(rows)
    (out / 'report.md').write_text(text, encoding='utf-8')
    figures = [
        plots.save_figure(plots.paired_differences_figure(rows), out / 'differences.png'),
        plots.save_figure(plots.cell_means_figure(rows), out / 'means.png'),
    ]
    print()
    print(text)
    print(f'written {out / "report.md"}, {", ".join(map(str, figures))}')
    return EXIT_OK


def robotarium_run(
    name_or_path: str,
    out: Path,
    *,
    planning: bool = True,
    barrier: bool = True,
    initialization: bool = True,
    seed: int = 0,
    plan_path: Path | None = None,
    json_out: dict[str, Any] | None = None,
) -> int:
    """Run the tube experiment on the bundled Robotarium simulator; print the verdict and metrics, write log and
    figure (``json_out``, when given, receives the verdict and metrics for ``--json``)."""

    from robotarium_exp.experiment import ExperimentConfig, plan_tracking, run_experiment
    from robotarium_exp.plots import experiment_figure
    from robotarium_exp.rps.robotarium import Robotarium
    from robotarium_exp.rps_alias import seed_rps
    from robotarium_exp.spec import ROBOTARIUM
    from vtube_planning.geometry.scene import load_scene
    from vtube_planning.plots import save_figure
    from vtube_planning.provenance import copy_scene, provenance

    scene = load_scene(name_or_path)
    plan = _plan_for(scene, plan_path=plan_path) if planning else None
    mode = 'planned' if planning else 'unplanned'
    log = out / f'experiment_{scene.name}_{mode}.npz'
    seed_rps(seed)  # V2's initialization draws from random and np.random
    result = run_experiment(
        Robotarium,
        scene,
        plan,
        ExperimentConfig(planning=planning, barrier=barrier),
        log_path=log,
        robotarium_kwargs={'skip_initialization': not initialization},
        log_meta={'provenance': provenance(scene=scene, plan_file=plan_path, seeds=[seed])},
    )
    e, m, b = result.errors, result.metrics, result.barrier
    hard = e['robots_too_close'] + e['robots_outside_boundaries']
    verdict = 'would run on the Robotarium' if hard == 0 else 'would NOT run on the Robotarium'
    print(
        f'Robotarium experiment, scene {scene.name}, {"with" if planning else "without"} planning, '
        f'barrier {"on" if barrier else "off"}: {verdict}'
    )
    print(f'  too close (pair-steps) {e["robots_too_close"]}')
    print(f'  outside boundaries     {e["robots_outside_boundaries"]}')
    print(f'  actuator-limit steps   {e["exceeded_actuator_limits"]}')
    print(
        f'  duration               {result.duration_s:.1f} s (initialization included: declare at least '
        f'{ROBOTARIUM.duration_factor * result.duration_s:.0f} s)'
    )
    print(f'  passing time           {m.passing_time_s:.2f} s; parked: {"yes" if result.completed else "no"}')
    print(f'  minimum distance       {m.min_distance_m:.3f} m between centres')
    print(f'  tube violations        {m.tube_violation_steps} robot-steps')
    print(
        f'  safety filter          correction mean {b["correction_mean_mps"]:.4f}, max {b["correction_max_mps"]:.4f} m/s, '
        f'total {b["intervention_m"]:.2f} m; failures {b["failures"]}'
    )
    print(
        f'  speed band             {100 * b["band_share"]:.2f} % of flying robot-steps in [v_min, v_max] '
        f'({100 * b["band_share_held"]:.2f} % where the filter kept it; band dropped in '
        f'{100 * b["band_dropped_share"]:.2f} % of steps)'
    )
    if plan is not None:
        tracked = plan_tracking(result, plan, scene)
        for phase in ('approach', 'dip', 'narrow'):
            ph = tracked[phase]
            if ph['steps']:
                print(
                    f'  tracking, {phase:<12} density error mean {100 * ph["density_error_mean"]:.0f} % '
                    f'(max {100 * ph["density_error_max"]:.0f} %), speed error mean '
                    f'{100 * ph["speed_error_mean"]:.0f} %'
                )
        print(
            f'  expansion              starts at {_seconds(tracked["expansion_start_s"])}; the front reaches the '
            f'narrowing at {_seconds(tracked["front_at_narrowing_s"])}'
        )
    figure = save_figure(experiment_figure(result, scene, plan), out / f'experiment_{scene.name}_{mode}.png')
    print(f'  written                {log}, {figure}, {copy_scene(scene, out)}')
    if json_out is not None:
        json_out |= {'log': str(log), 'would_run': hard == 0, 'errors': e, 'duration_s': result.duration_s}
        json_out |= {'metrics': m.to_json()}
    return EXIT_OK if hard == 0 else 1


def robotarium_compare(name_or_path: str, out: Path, *, seeds: int = 5, plan_path: Path | None = None) -> int:
    """Planned against unplanned over several initialization seeds; prints and writes the comparison table."""
    import json

    from robotarium_exp.compare import compare, comparison_table
    from vtube_planning.geometry.scene import load_scene
    from vtube_planning.swarm.metrics import strict_json

    scene = load_scene(name_or_path)
    plan = _plan_for(scene, plan_path=plan_path)
    with _progress_bar('experiments', 'run', quiet=False) as bar:
        bar.reset(total=2 * seeds)
        rows = compare(scene, plan, list(range(seeds)), run_done=bar.update)
    table = comparison_table(rows)
    out.mkdir(parents=True, exist_ok=True)
    (out / f'compare_{scene.name}.md').write_text(table, encoding='utf-8')
    (out / f'compare_{scene.name}.json').write_text(json.dumps(strict_json(rows), indent=1, allow_nan=False))
    print(f'scene {scene.name}, V2 initialization seeds 0..{seeds - 1}, mean [min, max]:')
    print(table)
    print(f'written {out / f"compare_{scene.name}.md"}, {out / f"compare_{scene.name}.json"}')
    return EXIT_OK


def _seconds(value: float | None) -> str:
    return 'never' if value is None else f'{value:.1f} s'


def submission_build(
    name_or_path: str,
    out: Path,
    *,
    planning: bool = True,
    plan_path: Path | None = None,
    declare: bool = True,
    seeds: int = 3,
    initializer_seeds: int = 200,
) -> int:
    """Write the single-file submission for a Robotarium scene (planned here, or from ``plan_path``).

    With ``declare``, the file is checked as ``vtube submission check`` does and rewritten with the duration to
    declare, and how it was derived, in its header; a file that fails the check keeps no declaration.
    """
    from submission.builder import build, write
    from submission.check import check
    from vtube_planning.geometry.scene import load_scene

    scene = load_scene(name_or_path)
    plan = _plan_for(scene, plan_path=plan_path)
    submission = build(scene, planning=planning, plan=plan)
    path = write(submission, out)
    print(
        f'submission for scene {submission.scene} ({submission.n_robots} robots, '
        f'{"with" if planning else "without"} planning): {path}'
    )
    if not declare:
        print(f'  check it before uploading:  vtube submission check {path}')
        return EXIT_OK
    report = check(path, seeds=seeds, initializer_seeds=initializer_seeds)
    if not _print_check(report) or report.declaration is None:
        print('  the file records no duration to declare: fix what failed and build again')
        return 1
    write(build(scene, planning=planning, plan=plan, declaration=report.declaration), out)
    print(f'  the header records the declaration: {submission.n_robots} robots, {report.declaration.duration_s} s')
    return EXIT_OK


def submission_check(
    path: Path,
    *,
    seeds: int = 3,
    initializer_seeds: int = 200,
    run_timeout_s: float | None = None,
    json_out: dict[str, Any] | None = None,
) -> int:
    """Preflight a submission file; prints the report and returns 0 when it passes, 1 when not (``json_out``, when
    given, receives the verdict, the declaration and the runs for ``--json``)."""
    from submission.check import RUN_TIMEOUT_S, check

    bars: list[Any] = []  # the initializer's bar, drawn from its first seed on (on a terminal)

    def seed_done() -> None:
        if not bars:
            bars.append(_progress_bar("V2's initializer", 'seed', quiet=False))
            bars[0].reset(total=initializer_seeds)
        bars[0].update()

    try:
        report = check(
            path,
            seeds=seeds,
            initializer_seeds=initializer_seeds,
            run_timeout_s=run_timeout_s or RUN_TIMEOUT_S,
            progress=lambda text: print(f'  ... {text}', file=sys.stderr, flush=True),
            seed_done=seed_done,
        )
    finally:
        for bar in bars:
            bar.close()
    passed = _print_check(report)
    if json_out is not None:
        json_out |= {'file': report.path, 'passed': passed, 'robots': report.robots}
        json_out |= {'declare_duration_s': report.declare_duration_s, 'problem': report.declaration_problem or None}
        json_out['runs'] = [
            {'backend': r.backend, 'seed': r.seed, 'ok': r.ok, 'returncode': r.returncode, 'summary': r.summary}
            for r in report.runs
        ]
    return EXIT_OK if passed else 1


def _print_check(report: CheckReport) -> bool:
    """Print a preflight's report; whether it passed."""
    from robotarium_exp.spec import ROBOTARIUM
    from submission.check import COUNTS

    print(f'submission {report.path}')
    if report.disallowed_imports:
        print(f'  FAIL: imports missing on the Robotarium server: {", ".join(report.disallowed_imports)}')
        return False
    print('  imports                only the standard library, numpy/scipy/matplotlib/cvxopt and rps: ok')
    print(
        f'  {"run":<16} {"done":>5} {"too close":>10} {"outside":>8} {"actuator":>9} {"min dist [m]":>13} '
        f'{"duration [s]":>13}'
    )
    for run in report.runs:
        label = f'{run.backend}' + (f' seed {run.seed}' if run.seed is not None else '')
        if run.timed_out_s is not None:
            print(f'  {label:<16} did not finish in {run.timed_out_s:g} s (raise --run-timeout if it should)')
            continue
        if run.summary is None and run.returncode == 0:
            print(f'  {label:<16} ran, but printed no vtube summary: not a file built by `vtube submission build`')
            continue
        if run.summary is None:
            print(f'  {label:<16} crashed (exit {run.returncode}): {run.stderr_tail.strip().splitlines()[-1:]}')
            continue
        counts = [run.count(key) for key in COUNTS]
        print(
            f'  {label:<16} {"yes" if run.summary["completed"] else "no":>5} {counts[0]:>10} {counts[1]:>8} '
            f'{counts[2]:>9} {run.summary["min_center_distance_m"]:>13.3f} '
            f'{run.summary["iterations"] * ROBOTARIUM.time_step_s:>13.1f}'
        )
    declared = report.declaration
    print(
        f'  declare                {report.robots or "?"} robots, '
        + (f'{declared.duration_s} s' if declared else 'no duration')
    )
    if declared:
        print(f'  duration from          {declared.basis()}')
    if report.header_declaration:
        print(f'  header records         {report.header_declaration.duration_s} s')
    if report.declaration_problem:
        print(f'  FAIL: {report.declaration_problem}')
    print(f'  verdict                {"PASS" if report.passed else "FAIL"}')
    return report.passed


def analyze(
    inputs: list[Path],
    scene_name: str | None,
    out: Path,
    *,
    plan_path: Path | None = None,
    compare: Path | None = None,
    topic_pattern: str | None = None,
    frame_pattern: str | None = None,
    topics: list[str] | None = None,
    world_frame: str | None = None,
    max_gap: str | None = None,
    collision_distance_m: float | None = None,
    json_out: dict[str, Any] | None = None,
) -> int:
    """Analyse returned data (testbed folder, .mat file, our logs, ROS bags), in a scene or without a tube; write
    metrics, report and figures."""
    from robotarium_exp.analysis.loaders import load_trajectory
    from robotarium_exp.analysis.report import analyse, write_report
    from robotarium_exp.analysis.trajectory import DEFAULT_MAX_GAP, MaxGap
    from vtube_planning.geometry.scene import load_scene
    from vtube_planning.provenance import copy_scene

    if plan_path is not None and scene_name is None:
        print('error: --plan needs the scene it was made for (--scene).', file=sys.stderr)
        return EXIT_BAD_INPUT
    scene = load_scene(scene_name) if scene_name is not None else None
    plan = _plan_for(scene, plan_path=plan_path) if plan_path is not None and scene is not None else None
    gap = MaxGap.parse(max_gap) if max_gap is not None else DEFAULT_MAX_GAP
    bag_options = {'topic_pattern': topic_pattern, 'frame_pattern': frame_pattern, 'topics': topics}
    options = {
        'scene': scene_name,
        'plan': str(plan_path) if plan_path else None,
        'max_gap': str(gap),
        'collision_distance_m': collision_distance_m,
        'world_frame': world_frame,
        **bag_options,
    }
    trajectory = load_trajectory(list(inputs), max_gap=gap, world_frame=world_frame, **bag_options)
    recorded = trajectory.source.get('tube_hash')
    if scene is not None and recorded is not None and recorded != scene.tube.fingerprint():
        name = trajectory.source.get('scene')
        where = f'scene {name!r}, whose tube' if name else 'a tube that'
        fix = f'--scene {name}' if name else 'the scene it was recorded in'
        print(
            f'error: the log was recorded in {where} is not the tube of scene {scene.name!r}; analyse it with '
            f'{fix}, or leave --scene out for the tube-free metrics.',
            file=sys.stderr,
        )
        return EXIT_BAD_INPUT
    results = {'data': analyse(trajectory, scene, plan, collision_distance_m=collision_distance_m, options=options)}
    if compare is not None:
        simulated = load_trajectory([compare], max_gap=gap)
        results['comparison'] = analyse(simulated, scene, plan, collision_distance_m=collision_distance_m)
    report = write_report(out, results, scene, plan)
    if scene is not None:
        copy_scene(scene, out)
    m = results['data'].metrics
    where = f'in scene {scene.name}' if scene is not None else 'without a tube'
    print(
        f'analysis of {trajectory.source.get("kind")} {trajectory.source.get("path")} {where}: '
        f'{trajectory.n_robots} robots, {m["frames"]} frames ({m["complete_frames"]} with every robot), '
        f'{len(m["gaps"])} gaps, {len(trajectory.source.get("ignored") or [])} topics/frames/variables ignored'
    )
    if m['min_distance_m'] is not None:
        pair = ' and '.join(m['min_distance_pair'])
        closest = f'minimum distance {m["min_distance_m"]:.3f} m ({pair}, t = {m["min_distance_time_s"]:.2f} s)'
    else:
        closest = 'one robot: no distances' if trajectory.n_robots < 2 else 'no two robots seen at the same time'
    collisions = (
        f'{m["collision_pairs"]} pairs closer than {m["collision_distance_m"]:.3f} m'
        if m['collision_distance_m'] is not None
        else 'collisions not counted (give --collision-distance)'
    )
    print(f'  {closest}, {collisions}')
    if scene is not None:
        passage = m['passage']
        if m['passing_time_s'] is None:
            print(f'  no passing time: {"; ".join(passage["unobserved"])}')
        else:
            print(f'  passing time {m["passing_time_s"]:.2f} s')
        print(f'  {m["tube_violation_steps"]} tube violations (robot-frames)')
    print(f'  written {report}, {out / "metrics.json"}')
    if json_out is not None:
        json_out |= m  # what metrics.json holds under "data"
    return EXIT_OK


def demo(out: Path) -> int:
    """The whole pipeline on the default Robotarium scene with the bundled simulator, into one report."""
    import os
    import subprocess
    import sys

    scene = 'robotarium_curve'
    plan_path = out / 'plan' / f'plan_{scene}.npz'  # planned once, by the first step
    steps = [
        ('plan', lambda: plan(scene, out / 'plan')),
        ('simulate with planning', lambda: simulate(scene, out / 'simulation', plan_path=plan_path)),
        ('simulate without planning', lambda: simulate(scene, out / 'simulation', planning=False)),
        (
            'build and check the submission',
            lambda: submission_build(
                scene, out / 'submission' / 'experiment.py', plan_path=plan_path, seeds=2, initializer_seeds=20
            ),
        ),
    ]
    for title, step in steps:
        print(f'\n== {title} ==')
        if step() != EXIT_OK:
            print(f'error: the demo stopped at "{title}"', file=sys.stderr)
            return 1
    print('\n== run the submission on the bundled simulator, as the testbed would, and analyse what it returns ==')
    returned = out / 'returned'
    returned.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, VTUBE_HEADLESS='1', MPLBACKEND='Agg')
    run = subprocess.run(
        [
            sys.executable,
            '-m',
            'robotarium_exp.rps_alias',
            '--seed',
            '0',
            str((out / 'submission' / 'experiment.py').resolve()),
        ],
        cwd=returned,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    (returned / 'log.txt').write_text(run.stdout + run.stderr, encoding='utf-8')
    if run.returncode != 0:
        print(f'error: the submission failed on the bundled simulator; see {returned / "log.txt"}', file=sys.stderr)
        return 1
    return analyze(
        [returned], scene, out / 'report', plan_path=plan_path, compare=out / 'simulation' / f'sim_{scene}_planned.npz'
    )


def _figure_path(out: Path) -> None:
    """Refuse, before any work, a figure file of a kind matplotlib cannot write."""
    from matplotlib.backend_bases import FigureCanvasBase

    kinds = FigureCanvasBase.get_supported_filetypes()
    if out.suffix.lstrip('.').lower() not in kinds:
        msg = (
            f'cannot write a figure to {out}: give a file ending in one of {", ".join("." + k for k in sorted(kinds))}.'
        )
        raise VtubeError(msg)


def _writable_folder(out: Path) -> None:
    """Refuse, before any run starts and without creating anything, an output folder that cannot be created or
    written: its nearest existing ancestor must be a folder this process may write in."""
    import os

    existing = out
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    problem = None
    if not existing.is_dir():
        problem = f'{existing} is not a folder'
    elif not os.access(existing, os.W_OK | os.X_OK):
        problem = f'no permission to write in {existing}'
    if problem is not None:
        msg = f'cannot write to {out} ({problem}); choose another --out before any run starts.'
        raise OSError(msg)


def _sizes(text: str) -> list[int]:
    try:
        sizes = [int(part) for part in text.split(',')]
    except ValueError:
        sizes = []
    if not sizes or min(sizes) < 1:
        msg = f'--sizes must be comma-separated whole numbers >= 1, like 20,40,80; got {text!r}.'
        raise VtubeError(msg)
    return sizes


def _progress_bar(what: str, unit: str, quiet: bool) -> Any:
    """A progress bar on stderr, drawn only on a terminal and without ``--quiet``."""
    from tqdm import tqdm

    return tqdm(desc=what, unit=unit, disable=quiet or not sys.stderr.isatty(), file=sys.stderr, leave=False)


def _whole(text: str) -> int:
    """An argparse type: a whole number >= 0."""
    if not text.strip().isdigit():
        msg = f'{text!r} is not a whole number >= 0'
        raise argparse.ArgumentTypeError(msg)
    return int(text)


def _count(text: str) -> int:
    """An argparse type: a whole number >= 1."""
    value = _whole(text)
    if value < 1:
        msg = f'{text!r} is not a whole number >= 1'
        raise argparse.ArgumentTypeError(msg)
    return value


def _regex(text: str) -> str:
    """An argparse type: a regular expression Python can compile."""
    import re

    try:
        re.compile(text)
    except re.error as err:
        msg = f'{text!r} is not a regular expression ({err})'
        raise argparse.ArgumentTypeError(msg) from err
    return text


def _positive(text: str) -> float:
    """An argparse type: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        msg = f'{text!r} is not a number > 0'
        raise argparse.ArgumentTypeError(msg)
    return value


def _execution_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        '--workers', type=_whole, default=0, help='local processes (default 0: one per core; 1: this process)'
    )
    parser.add_argument(
        '--scheduler', default=None, help='run on this Dask scheduler, tcp://HOST:PORT (vtube[cluster])'
    )
    parser.add_argument(
        '--scheduler-timeout',
        type=_positive,
        default=10.0,
        help='seconds to wait for the scheduler (default 10)',
    )
    parser.add_argument('--quiet', action='store_true', help='no progress bar (none is drawn unless on a terminal)')


def _execution(args: argparse.Namespace) -> Execution:
    return Execution(args.workers, args.scheduler, args.scheduler_timeout, args.quiet)


EXIT_CODES = (
    'exit codes: 0 done, every check held; 1 a check or claim failed; 2 bad input or refused work; 130 interrupted.'
)


class _HelpFormatter(argparse.HelpFormatter):
    """Help that shows each option's default (when it has one worth showing)."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        text = action.help or ''
        default = action.default
        shown = not (default is None or default is False or default == argparse.SUPPRESS) and '(default' not in text
        return f'{text} (default: %(default)s)' if shown and action.option_strings else text


class _Parser(argparse.ArgumentParser):
    """Every vtube (sub)command's parser: defaults in the help, the exit codes below it."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault('formatter_class', _HelpFormatter)
        kwargs.setdefault('epilog', EXIT_CODES)
        super().__init__(*args, **kwargs)


def _parser() -> argparse.ArgumentParser:
    from vtube_planning import __version__

    parser = _Parser(
        prog='vtube',
        description='Speed and density planning for a speed-constrained robot swarm through a virtual tube.',
    )
    parser.add_argument('--version', action='version', version=f'vtube {__version__}')
    commands = parser.add_subparsers(dest='command', required=True, metavar='COMMAND')
    scene = commands.add_parser('scene', help='list and draw scenes')
    scene_commands = scene.add_subparsers(dest='scene_command', required=True, metavar='SUBCOMMAND')
    scene_commands.add_parser('list', help='list the shipped scenes')
    show = scene_commands.add_parser('show', help="print a scene's summary and draw it")
    show.add_argument('scene', help='a shipped scene name (see `vtube scene list`) or a .toml file')
    show.add_argument('--out', type=Path, default=None, help='write the figure here (e.g. scene.png)')
    export = scene_commands.add_parser('export', help="write a shipped scene's file, to edit")
    export.add_argument('scene', help='a shipped scene name (see `vtube scene list`)')
    export.add_argument('file', type=Path, help='the .toml file to write (must not exist)')
    planner = commands.add_parser('plan', help="plan speed and density along a scene's tube")
    planner.add_argument('--json', action='store_true', help='print the result as one JSON object on stdout')
    planner.add_argument('scene', help='a shipped scene name (see `vtube scene list`) or a .toml file')
    planner.add_argument('--out', type=Path, required=True, help='folder for the plan file and its figure')
    planner.add_argument(
        '--method',
        choices=('convex', 'polynomial'),
        default='convex',
        help="convex: slowness form (default); polynomial: the paper's cubic segments",
    )
    planner.add_argument(
        '--grid-step',
        type=_positive,
        default=None,
        dest='grid_step_m',
        help="planning grid step in m, > 0 (default: the scene's)",
    )
    sim = commands.add_parser('simulate', help='fly the swarm through a scene, with or without planning')
    sim.add_argument('--json', action='store_true', help='print the result as one JSON object on stdout')
    sim.add_argument('scene', help='a shipped scene name or a .toml file')
    sim.add_argument('--out', type=Path, required=True, help='folder for the log, figures and GIF')
    sim.add_argument('--no-planning', action='store_true', help='constant mid-range speed and constant r_a')
    sim.add_argument('--n', type=_count, default=None, dest='n_robots', help="swarm size, >= 1 (default: the scene's)")
    sim.add_argument('--seed', type=_whole, default=0, help='seed of the initial formation jitter, >= 0')
    sim.add_argument(
        '--acceleration-limits',
        action='store_true',
        help='make every robot obey the acceleration limits (3), (4), not only the plan',
    )
    sim.add_argument('--animate', action='store_true', help='also write an animated GIF')
    sim.add_argument('--quiet', action='store_true', help='no progress bar (none is drawn unless on a terminal)')
    sim.add_argument('--plan', type=Path, default=None, help='fly this plan file (vtube plan) instead of planning')
    sim.add_argument(
        '--replan-every',
        type=_positive,
        default=0.0,
        dest='replan_every_s',
        metavar='S',
        help='replan the rest of the tube every S seconds from the measured state, > 0 (default: never)',
    )
    stu = commands.add_parser('study', help="the paper's comparison on scenes A-D with and without planning")
    stu.add_argument('--out', type=Path, required=True, help='folder for runs.csv, study.md, study.json, study.png')
    stu.add_argument('--seeds', type=_count, default=5, help='number of seeds n >= 1 (seeds 0..n-1)')
    stu.add_argument('--scenes', default='A,B,C,D', help='comma-separated scene names')
    stu.add_argument('--acceleration-limits', action='store_true', help='apply (3), (4) to every robot')
    stu.add_argument(
        '--baselines',
        action='store_true',
        help='add optimized flocking and NMPC on scenes C and D (NMPC: about a minute per run)',
    )
    _execution_arguments(stu)
    abl = commands.add_parser('ablation', help='what each part of the method buys: the ablation grid, with intervals')
    abl.add_argument('--out', type=Path, required=True, help='folder for runs.csv, report.md and the figures')
    abl.add_argument('--scenes', default='C,D', help='comma-separated scene names')
    abl.add_argument('--sizes', default='20,40,80', help='comma-separated swarm sizes N')
    abl.add_argument('--seeds', type=_count, default=10, help='number of seeds n >= 1 (seeds 0..n-1)')
    abl.add_argument(
        '--models', default='paper,acceleration limits', help="robot models: 'paper' and/or 'acceleration limits'"
    )
    abl.add_argument(
        '--saturations', default='radial,forward', help="'radial' (the paper's sat) and/or 'forward' (never backwards)"
    )
    _execution_arguments(abl)
    camp = commands.add_parser('campaign', help='run a study declared in a TOML file, anywhere, resumably')
    camp_commands = camp.add_subparsers(dest='campaign_command', required=True, metavar='SUBCOMMAND')
    camp_run = camp_commands.add_parser('run', help='run (or resume) a campaign and write its report')
    camp_run.add_argument('file', type=Path, help='the campaign .toml file (see docs/faults/campaign.toml)')
    camp_run.add_argument(
        '--out',
        type=Path,
        default=None,
        help="folder for runs.csv, campaign.json and the report (default: the file's out)",
    )
    _execution_arguments(camp_run)
    camp_report = camp_commands.add_parser('report', help="a campaign folder's tables and figures, from runs.csv")
    camp_report.add_argument('folder', type=Path, help='the folder a campaign ran into')
    robo = commands.add_parser('robotarium', help='the tube experiment on the bundled Robotarium simulator')
    robo_commands = robo.add_subparsers(dest='robotarium_command', required=True, metavar='SUBCOMMAND')
    run = robo_commands.add_parser('run', help='run the experiment, print the testbed verdict and metrics')
    run.add_argument('--json', action='store_true', help='print the result as one JSON object on stdout')
    run.add_argument('scene', help='a Robotarium scene (robotarium_trapezoid, robotarium_curve) or a .toml file')
    run.add_argument('--out', type=Path, required=True, help='folder for the log and the figure')
    run.add_argument('--no-planning', action='store_true', help='constant mid-range speed and constant r_a')
    run.add_argument('--no-barrier', action='store_true', help='send the swarm commands without the certificate')
    run.add_argument('--no-initialization', action='store_true', help='start at the initial conditions directly')
    run.add_argument('--seed', type=_whole, default=0, help='seed of the initialization (charger slots, escapes), >= 0')
    run.add_argument('--plan', type=Path, default=None, help='fly this plan file (vtube plan) instead of planning')
    cmp_cmd = robo_commands.add_parser('compare', help='planned against unplanned over initialization seeds')
    cmp_cmd.add_argument('scene', help='a Robotarium scene or a .toml file')
    cmp_cmd.add_argument('--out', type=Path, required=True, help='folder for the table (.md) and the rows (.json)')
    cmp_cmd.add_argument('--seeds', type=_count, default=5, help='initialization seeds 0..n-1, n >= 1')
    cmp_cmd.add_argument('--plan', type=Path, default=None, help='fly this plan file (vtube plan)')
    sub = commands.add_parser('submission', help='build and check the single file for the remote Robotarium')
    sub_commands = sub.add_subparsers(dest='submission_command', required=True, metavar='SUBCOMMAND')
    build_cmd = sub_commands.add_parser('build', help='write the submission file for a Robotarium scene')
    build_cmd.add_argument('scene', help='robotarium_trapezoid, robotarium_curve or a .toml file')
    build_cmd.add_argument('--out', type=Path, required=True, help='the .py file to write')
    build_cmd.add_argument('--no-planning', action='store_true', help='constant speed and r_a (the comparison)')
    build_cmd.add_argument(
        '--plan', type=Path, default=None, help='embed this plan file (vtube plan) instead of planning'
    )
    build_cmd.add_argument(
        '--no-declare', action='store_true', help='skip the check that derives the duration to declare'
    )
    build_cmd.add_argument('--seeds', type=_count, default=3, help='checking runs on the bundled simulator, >= 1')
    build_cmd.add_argument(
        '--initializer-seeds',
        type=_count,
        default=200,
        help="V2's initializer alone, for the duration to declare, >= 1",
    )
    check_cmd = sub_commands.add_parser('check', help='preflight a submission on the simulators')
    check_cmd.add_argument('--json', action='store_true', help='print the result as one JSON object on stdout')
    check_cmd.add_argument('file', type=Path, help='the submission .py file')
    check_cmd.add_argument(
        '--seeds', type=_count, default=3, help='runs on the bundled simulator (seeds 0..n-1), n >= 1'
    )
    check_cmd.add_argument(
        '--initializer-seeds',
        type=_count,
        default=200,
        help="V2's initializer alone, for the duration to declare, >= 1",
    )
    check_cmd.add_argument(
        '--run-timeout',
        type=_positive,
        default=None,
        dest='run_timeout_s',
        help='seconds after which a run of the file is stopped and reported as not finished (default 900)',
    )
    ana = commands.add_parser('analyze', help='metrics, figures and a report of returned or recorded data')
    ana.add_argument('--json', action='store_true', help='print the result as one JSON object on stdout')
    ana.add_argument(
        'inputs',
        type=Path,
        nargs='+',
        help='a folder of vtube_*.npy, a .npz log, a .mat file, .bag files, a ROS2 bag folder or .mcap/.db3 files',
    )
    ana.add_argument('--scene', default=None, help='the scene the data was recorded in (omit: no tube metrics)')
    ana.add_argument('--out', type=Path, required=True, help='folder for metrics.json, report.md and figures')
    ana.add_argument('--plan', type=Path, default=None, help='a plan file (vtube plan) to track against')
    ana.add_argument('--compare', type=Path, default=None, help='a simulation log to show side by side')
    ana.add_argument('--topic', action='append', default=None, dest='topics', help='bag topic(s) to read')
    ana.add_argument(
        '--topic-pattern', type=_regex, default=None, help='regex with a (?P<robot>...) group for bag topics'
    )
    ana.add_argument(
        '--frame-pattern', type=_regex, default=None, help='regex with a (?P<robot>...) group for /tf child frames'
    )
    ana.add_argument('--world-frame', default=None, help='reference frame of the robots (/tf parent, header.frame_id)')
    ana.add_argument(
        '--max-gap',
        default=None,
        help="longest hole in a robot's samples that is interpolated, e.g. 3periods (default), 0.25s, 250ms",
    )
    ana.add_argument(
        '--collision-distance',
        type=_positive,
        default=None,
        dest='collision_distance_m',
        help="centre distance counted as a collision (default: the scene's 2 r_p; none without a scene)",
    )
    dem = commands.add_parser('demo', help='the whole pipeline on the bundled simulator, into one report')
    dem.add_argument('--out', type=Path, required=True, help='folder for everything the demo writes')
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``vtube`` console script; returns the exit code. With ``--json`` the command's readable
    output goes to stderr and its result, one JSON object, to stdout."""
    import contextlib
    import json

    from vtube_planning.provenance import command_line
    from vtube_planning.swarm.metrics import strict_json

    args = _parser().parse_args(argv)
    words = ['vtube', *(sys.argv[1:] if argv is None else argv)]
    if not getattr(args, 'json', False):
        with command_line(words):
            return _dispatch(args, None)
    result: dict[str, Any] = {}
    with contextlib.redirect_stdout(sys.stderr), command_line(words):
        code = _dispatch(args, result)
    if result:
        print(json.dumps(strict_json(result | {'exit_code': code}), allow_nan=False))
    return code


def _dispatch(args: argparse.Namespace, json_out: dict[str, Any] | None) -> int:
    """Run the command ``args`` names; ``json_out`` receives its result for ``--json``."""
    try:
        if args.command in ('plan', 'simulate', 'robotarium', 'analyze', 'demo'):
            _writable_folder(args.out)  # before any work: campaigns check theirs in _run_campaign
        if args.command == 'plan':
            return plan(args.scene, args.out, args.method, args.grid_step_m, json_out)
        if args.command == 'simulate':
            return simulate(
                args.scene,
                args.out,
                planning=not args.no_planning,
                n_robots=args.n_robots,
                seed=args.seed,
                acceleration_limits=args.acceleration_limits,
                animate=args.animate,
                plan_path=args.plan,
                replan_every_s=args.replan_every_s,
                json_out=json_out,
                quiet=args.quiet,
            )
        if args.command == 'analyze':
            return analyze(
                args.inputs,
                args.scene,
                args.out,
                plan_path=args.plan,
                compare=args.compare,
                topic_pattern=args.topic_pattern,
                frame_pattern=args.frame_pattern,
                topics=args.topics,
                world_frame=args.world_frame,
                max_gap=args.max_gap,
                collision_distance_m=args.collision_distance_m,
                json_out=json_out,
            )
        if args.command == 'demo':
            return demo(args.out)
        if args.command == 'submission' and args.submission_command == 'build':
            return submission_build(
                args.scene,
                args.out,
                planning=not args.no_planning,
                plan_path=args.plan,
                declare=not args.no_declare,
                seeds=args.seeds,
                initializer_seeds=args.initializer_seeds,
            )
        if args.command == 'submission':
            return submission_check(
                args.file,
                seeds=args.seeds,
                initializer_seeds=args.initializer_seeds,
                run_timeout_s=args.run_timeout_s,
                json_out=json_out,
            )
        if args.command == 'robotarium' and args.robotarium_command == 'compare':
            return robotarium_compare(args.scene, args.out, seeds=args.seeds, plan_path=args.plan)
        if args.command == 'robotarium':
            return robotarium_run(
                args.scene,
                args.out,
                planning=not args.no_planning,
                barrier=not args.no_barrier,
                initialization=not args.no_initialization,
                seed=args.seed,
                plan_path=args.plan,
                json_out=json_out,
            )
        if args.command == 'ablation':
            return ablation(
                args.out,
                scenes=args.scenes.split(','),
                sizes=_sizes(args.sizes),
                seeds=args.seeds,
                models=args.models.split(','),
                saturations=args.saturations.split(','),
                execution=_execution(args),
            )
        if args.command == 'study':
            return study(
                args.out,
                scenes=args.scenes.split(','),
                seeds=args.seeds,
                acceleration_limits=args.acceleration_limits,
                baselines=args.baselines,
                execution=_execution(args),
            )
        if args.command == 'campaign' and args.campaign_command == 'run':
            return campaign_run(args.file, args.out, _execution(args))
        if args.command == 'campaign':
            return campaign_report(args.folder)
        if args.scene_command == 'list':
            return scene_list()
        if args.scene_command == 'export':
            return scene_export(args.scene, args.file)
        return scene_show(args.scene, args.out)
    except (VtubeError, RobotariumExpError, RobotariumError, MappingError, OSError) as err:
        print('error: ' + ' '.join(str(err).split()), file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print('interrupted.', file=sys.stderr)
        return EXIT_INTERRUPTED
