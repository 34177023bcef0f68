"""``vtube robotarium run|compare``: the tube experiment on the bundled Robotarium simulator."""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from vtube.cli.arguments import SEEDS_HELP, seed, seeds, testbed_model_name, writable_folder
from vtube.cli.command import EXIT_FAILED, EXIT_OK, BadInput, Command, View
from vtube.cli.render import progress_bar
from vtube_planning.files import write_atomically
from vtube_planning.studies.seeds import seeds_text

if TYPE_CHECKING:
    from robotarium_exp.experiment import ExperimentConfig, ExperimentResult
    from robotarium_exp.tracking import PlanTracking
    from robotarium_exp.verdict import VerifierVerdict
    from vtube_planning.geometry.scene import Scene


@dataclass(frozen=True)
class RobotariumRun:
    """An experiment flown on the bundled simulator, the testbed's verdict on it, how it followed its plan (None:
    unplanned) and the files written: log, figure, the scene's copy; ``initialized``: it flew from V2's
    initialization, as the testbed starts (False: from the formation, ``--no-initialization``)."""

    scene: Scene
    config: ExperimentConfig
    result: ExperimentResult
    verdict: VerifierVerdict
    tracking: PlanTracking | None
    written: tuple[Path, Path, Path]
    initialized: bool = True


@dataclass(frozen=True)
class Comparison:
    """Planned against unplanned over initialization seeds (in the order run): the table, the files written and the
    runs that failed (`robotarium_exp.compare.failed_runs`)."""

    scene: str
    seeds: tuple[int, ...]
    table: str
    written: tuple[Path, Path]
    failed: tuple[str, ...] = ()


def experiment_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        'scene', help='a Robotarium scene (robotarium_trapezoid, robotarium_curve, their _20 variants) or a .toml file'
    )
    parser.add_argument('--out', type=Path, required=True, help='folder for the log and the figure')
    parser.add_argument('--no-planning', action='store_true', help='constant mid-range speed and constant r_a')
    parser.add_argument('--no-barrier', action='store_true', help='send the swarm commands without the certificate')
    parser.add_argument(
        '--no-initialization',
        action='store_true',
        help="start at the initial conditions directly: not the testbed's start, so not its verdict",
    )
    parser.add_argument(
        '--seed', type=seed, default=0, help='seed of the initialization (charger slots, escapes), >= 0'
    )
    parser.add_argument('--plan', type=Path, default=None, help='fly this plan file (vtube plan) instead of planning')
    testbed_model_argument(parser)


def testbed_model_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        '--testbed-model',
        type=testbed_model_name,
        default='ideal',
        help="what the real robots do to commands and poses: ideal (V2's simulator), fitted (delay, lag, gains, "
        'noise fitted to real runs: robotarium_exp.rps.testbed_model), fitted:K (delay and lag times K)',
    )


def experiment(args: argparse.Namespace) -> RobotariumRun:
    """Run the tube experiment on the bundled Robotarium simulator; write its log, figure and the scene's copy."""
    from robotarium_exp.experiment import ExperimentConfig, run_experiment
    from robotarium_exp.fit import require_fit
    from robotarium_exp.plots import experiment_figure
    from robotarium_exp.rps.robotarium import Robotarium
    from robotarium_exp.rps_alias import seed_rps
    from robotarium_exp.scene import load_scene
    from robotarium_exp.tracking import plan_tracking
    from robotarium_exp.verdict import testbed_verdict
    from vtube.pipeline import plan_for
    from vtube_planning.plots import save_figure
    from vtube_planning.provenance import copy_scene, provenance

    out: Path = args.out
    writable_folder(out)
    scene = load_scene(args.scene)
    require_fit(scene)
    plan = None if args.no_planning else plan_for(scene, plan_file=args.plan)
    config = ExperimentConfig(planning=not args.no_planning, barrier=not args.no_barrier)
    stem = f'experiment_{scene.name}_{"planned" if config.planning else "unplanned"}'
    seed_rps(args.seed)  # V2's initialization draws from random and np.random
    result = run_experiment(
        Robotarium,
        scene,
        plan,
        config,
        log_path=out / f'{stem}.npz',
        robotarium_kwargs={'skip_initialization': args.no_initialization, 'testbed_model': args.testbed_model},
        log_meta={'provenance': provenance(scene=scene, plan_file=args.plan, seeds=[args.seed])},
    )
    tracking = plan_tracking(result.arrays, plan, scene) if plan is not None else None
    figure = save_figure(experiment_figure(result, scene, plan), out / f'{stem}.png')
    written = (out / f'{stem}.npz', figure, copy_scene(scene, out))
    verdict = testbed_verdict(result)
    return RobotariumRun(scene, config, result, verdict, tracking, written, not args.no_initialization)


def experiment_view(run: RobotariumRun) -> View:
    from robotarium_exp.verdict import flight_failures

    verdict, m, b = run.verdict, run.result.metrics, run.result.barrier
    failures = flight_failures(run.result)
    said = 'would run on the Robotarium' if verdict.would_run else 'would NOT run on the Robotarium'
    lines = [
        (
            f'Robotarium experiment, scene {run.scene.name}, {"with" if run.config.planning else "without"} planning, '
            f'barrier {"on" if run.config.barrier else "off"}: {said}'
        ),
        f'  too close (pair-steps) {verdict.counts.too_close}',
        f'  outside boundaries     {verdict.counts.outside}',
        f'  actuator-limit steps   {verdict.counts.actuator}',
        (
            f'  duration               {verdict.duration_s:.1f} s (initialization included: declare at least '
            f'{verdict.declare_at_least_s:.0f} s)'
        ),
        f'  passing time           {m.passing_time_s:.2f} s; parked: {"yes" if run.result.completed else "no"}',
        f'  minimum distance       {m.min_distance_m:.3f} m between centres',
        f'  tube violations        {m.tube_violation_steps} robot-steps',
        (
            f'  safety filter          correction mean {b.correction_mean_mps:.4f}, max {b.correction_max_mps:.4f} '
            f'm/s, total {b.intervention_m:.2f} m; failures {b.failures}'
        ),
        (
            f'  speed band             {100 * b.band_share:.2f} % of flying robot-steps in [v_min, v_max] '
            f'({100 * b.band_share_held:.2f} % where the filter kept it; band dropped in '
            f'{100 * b.band_dropped_share:.2f} % of steps)'
        ),
    ]
    if run.tracking is not None:
        lines += _tracking_lines(run.tracking)
    lines.append(f'  flight                 {"FAILED: " + "; ".join(failures) if failures else FLEW}')
    lines += [] if run.initialized else [f'  start                  {NOT_THE_TESTBEDS_START}']
    lines.append(f'  written                {", ".join(map(str, run.written))}')
    data = {'log': str(run.written[0]), 'would_run': verdict.would_run, 'errors': run.result.errors.to_json()}
    data |= {'duration_s': verdict.duration_s, 'metrics': m.to_json()}
    data |= {'failures': list(failures)} if failures else {}
    data |= {'initialized': run.initialized}
    return View(tuple(lines), data, exit_code=EXIT_FAILED if failures else EXIT_OK)


NOT_THE_TESTBEDS_START = (
    "from the formation (--no-initialization), not from the testbed's start: a tube that flies clean from here can "
    "fail after V2's initialization; the verdict to trust is a run without it (submission build always flies it)"
)
FLEW = 'succeeded: the testbed would run it; every robot passed and parked; no collision; no body on a wall'


def _tracking_lines(tracked: PlanTracking) -> list[str]:
    """How the run followed its plan, phase by phase, and when the swarm expanded."""
    lines = [
        f'  tracking, {phase:<12} density error mean {100 * (ph.density_error_mean or 0.0):.0f} % '
        f'(max {100 * (ph.density_error_max or 0.0):.0f} %), speed error mean {100 * (ph.speed_error_mean or 0.0):.0f} %'
        for phase, ph in tracked.phases().items()
        if ph.steps
    ]
    lines.append(
        f'  expansion              starts at {_seconds(tracked.expansion_start_s)}; the front reaches the '
        f'narrowing at {_seconds(tracked.front_at_narrowing_s)}'
    )
    return lines


def _seconds(value: float | None) -> str:
    return 'never' if value is None else f'{value:.1f} s'


def comparison_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('scene', help='a Robotarium scene or a .toml file')
    parser.add_argument('--out', type=Path, required=True, help='folder for the table (.md) and the rows (.json)')
    parser.add_argument('--seeds', type=seeds, default='5', help=f'initialization {SEEDS_HELP} (default 5: 0-4)')
    parser.add_argument(
        '--confirm-seeds',
        type=seeds,
        default=(),
        help='fresh initialization seeds also run, e.g. 10-19: pooled with --seeds in the verdicts, unless --held-out',
    )
    parser.add_argument(
        '--held-out',
        action='store_true',
        help='test the --confirm-seeds apart, only on the claims the other seeds found (a replication)',
    )
    parser.add_argument('--plan', type=Path, default=None, help='fly this plan file (vtube plan)')
    testbed_model_argument(parser)


def comparison(args: argparse.Namespace) -> Comparison:
    """Planned against unplanned over several initialization seeds; writes the table and the rows."""
    import json

    from robotarium_exp.compare import compare, comparison_table, failed_runs, paired_table
    from robotarium_exp.fit import require_fit
    from robotarium_exp.scene import load_scene
    from vtube.pipeline import plan_for
    from vtube_planning.provenance import made_text, provenance, source_commit

    out: Path = args.out
    if args.held_out and not args.confirm_seeds:
        raise BadInput('--held-out needs seeds to hold out: give --confirm-seeds too, e.g. --confirm-seeds 10-19.')
    writable_folder(out)
    scene = load_scene(args.scene)
    require_fit(scene)
    plan = plan_for(scene, plan_file=args.plan)
    reused = sorted(set(args.seeds) & set(args.confirm_seeds))
    if reused:
        raise BadInput(f'--confirm-seeds must be fresh seeds: {reused} are in --seeds too; give others, e.g. 10-19.')
    everything = (*args.seeds, *args.confirm_seeds)
    with progress_bar('experiments', 'run') as bar:
        bar.reset(total=2 * len(everything))
        rows = compare(scene, plan, list(everything), run_done=bar.update, testbed_model=args.testbed_model)
    table = comparison_table(rows) + '\n' + paired_table(rows, args.confirm_seeds if args.held_out else ())
    out.mkdir(parents=True, exist_ok=True)
    written = (out / f'compare_{scene.name}.md', out / f'compare_{scene.name}.json')
    made = made_text(provenance() | {'commit': source_commit()})
    write_atomically(written[0], f'{comparison_head(scene.name, everything)}\n\n{table}\nThe runs were {made}.\n')
    write_atomically(written[1], json.dumps([row.to_json() for row in rows], indent=1, allow_nan=False))
    return Comparison(scene.name, everything, table, written, failed_runs(rows))


def comparison_head(scene: str, seeds: tuple[int, ...]) -> str:
    """What a comparison's table shows: the scene and the seeds run."""
    return f'scene {scene}, V2 initialization seeds {seeds_text(seeds)}, mean [min, max]:'


def comparison_view(result: Comparison) -> View:
    lines = (
        comparison_head(result.scene, result.seeds),
        result.table,
        f'written {result.written[0]}, {result.written[1]}',
    )
    failed = tuple(f'FAILED {run}' for run in result.failed)
    return View(lines + failed, exit_code=EXIT_FAILED if failed else EXIT_OK)


COMMANDS = (
    Command(
        'robotarium run',
        'run the experiment, print the testbed verdict and metrics',
        experiment_arguments,
        experiment,
        experiment_view,
        json=True,
    ),
    Command(
        'robotarium compare',
        'planned against unplanned over initialization seeds',
        comparison_arguments,
        comparison,
        comparison_view,
    ),
)
