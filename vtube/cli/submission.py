"""``vtube submission build|check``: the single file for the remote Robotarium, and its preflight."""

from __future__ import annotations

import argparse
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

from vtube.cli.arguments import SEEDS_HELP, count, positive, seeds, testbed_model_name, writable_folder
from vtube.cli.command import EXIT_FAILED, EXIT_OK, BadInput, Command, View
from vtube.cli.render import progress_bar, tell

if TYPE_CHECKING:
    from tqdm import tqdm

    from submission.builder import Submission
    from submission.check import CheckReport, RunReport
    from submission.declaration import Declaration
    from vtube.pipeline import WrittenSubmission


def initializer_seeds_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        '--initializer-seeds', type=count, default=200, help="V2's initializer alone, for the duration to declare, >= 1"
    )
    parser.add_argument(
        '--testbed-models',
        type=testbed_models,
        default=None,
        help='the runs fly under these testbed models, ideal first (default ideal,fitted,fitted:2: ideal and fitted '
        'decide the verdict, the others are stress tests reported with their margins)',
    )
    parser.add_argument(
        '--margin-seeds',
        type=margin_seeds,
        default=(),
        help='also search the delay margin: the largest multiple of the fitted delay and lag (1x, 1.5x, 2x, ...) at '
        f'which every run over these seeds stays clean, {SEEDS_HELP}, at least 10 (default: no search; it flies '
        'up to 70 more runs)',
    )


def margin_seeds(text: str) -> tuple[int, ...]:
    """An argparse type: the seeds of the delay margin's runs at each multiple, at least 10 of them."""
    from submission.delay_margin import MIN_SEEDS

    chosen = seeds(text)
    if len(chosen) < MIN_SEEDS:
        msg = f'{text!r} gives {len(chosen)} seeds; a delay margin rests on at least {MIN_SEEDS} (e.g. {MIN_SEEDS})'
        raise argparse.ArgumentTypeError(msg)
    return chosen


def testbed_models(text: str) -> tuple[str, ...]:
    """An argparse type: testbed model names, comma-separated, ``ideal`` first."""
    names = tuple(name.strip() for name in text.split(','))
    for name in names:
        testbed_model_name(name)
    if names[0] != 'ideal':
        msg = f'{text!r}: the first testbed model must be ideal (the simulator the testbed accepts files by)'
        raise argparse.ArgumentTypeError(msg)
    return names


def build_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('scene', help='robotarium_trapezoid, robotarium_curve (and their _20 variants) or a .toml file')
    parser.add_argument('--out', type=Path, required=True, help='the .py file to write')
    parser.add_argument('--no-planning', action='store_true', help='constant speed and r_a (the comparison)')
    parser.add_argument('--plan', type=Path, default=None, help='embed this plan file (vtube plan) instead of planning')
    parser.add_argument('--no-declare', action='store_true', help='skip the check that derives the duration to declare')
    parser.add_argument(
        '--seeds', type=seeds, default='3', help=f'checking runs on the bundled simulator, {SEEDS_HELP} (default 3)'
    )
    initializer_seeds_argument(parser)


def build(args: argparse.Namespace) -> WrittenSubmission:
    """Write the submission for a Robotarium scene; unless ``--no-declare``, checked and rewritten with the
    duration to declare (`vtube.pipeline.build_submission`), each stage of the check told on stderr as it starts."""
    from vtube.pipeline import build_submission

    _writable_file(args.out)
    with initializer_bar(args.initializer_seeds) as seed_done:
        return build_submission(
            args.scene,
            args.out,
            planning=not args.no_planning,
            plan_file=args.plan,
            declare=not args.no_declare,
            seeds=args.seeds,
            initializer_seeds=args.initializer_seeds,
            testbed_models=args.testbed_models,
            margin_seeds=args.margin_seeds,
            progress=tell,
            seed_done=seed_done,
        )


def _writable_file(out: Path) -> None:
    """Refuse, before minutes of checks, an ``--out`` that names a folder or lies where no file can be written."""
    if out.is_dir():
        msg = f'--out {out} is a folder; give the .py file to write, e.g. --out {out / "experiment.py"}.'
        raise BadInput(msg)
    writable_folder(out.parent)


def build_view(written: WrittenSubmission) -> View:
    sub = written.submission
    head = (
        f'submission for scene {sub.scene} ({sub.n_robots} robots, {"with" if sub.planned else "without"} '
        f'planning): {written.path}'
    )
    if written.report is None:
        return View((head, f'  check it before uploading:  vtube submission check {written.path}'))
    lines = (head, *check_lines(written.report))
    if written.declaration is None:
        return View(
            (*lines, '  the file records no duration to declare: fix what failed and build again'), None, EXIT_FAILED
        )
    declared = f'  the header records the declaration: {sub.n_robots} robots, {written.declaration.duration_s} s'
    return View((*lines, *_not_for_upload(written.declaration, sub), declared))


def _not_for_upload(declaration: Declaration, sub: Submission) -> list[str]:
    """A preview's declaration (fewer initializer seeds than a full build): why the file is not for upload, and the
    command that builds the one to upload ([] for a full build's)."""
    if declaration.for_upload:
        return []
    command = f'vtube submission build {sub.scene} --out experiment.py{"" if sub.planned else " --no-planning"}'
    return [f'  {declaration.not_for_upload()[0]}; its header says so. Build the file to upload with `{command}`.']


def preflight_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('file', type=Path, help='the submission .py file')
    parser.add_argument(
        '--seeds', type=seeds, default='3', help=f'runs on the bundled simulator, {SEEDS_HELP} (default 3)'
    )
    initializer_seeds_argument(parser)
    parser.add_argument(
        '--run-timeout',
        type=positive,
        default=None,
        dest='run_timeout_s',
        help='seconds after which a run of the file is stopped and reported as not finished (default 900)',
    )


@contextmanager
def initializer_bar(total: int) -> Iterator[Callable[[], None]]:
    """The ``seed_done`` of a check: the initializer's bar, drawn from its first seed on (on a terminal)."""
    bars: list[tqdm] = []

    def seed_done() -> None:
        if not bars:
            bars.append(progress_bar("V2's initializer", 'seed'))
            bars[0].reset(total=total)
        bars[0].update()

    try:
        yield seed_done
    finally:
        for bar in bars:
            bar.close()


def preflight(args: argparse.Namespace) -> CheckReport:
    """Preflight a submission file, each stage told on stderr as it starts."""
    from submission.check import RUN_TIMEOUT_S, check

    with initializer_bar(args.initializer_seeds) as seed_done:
        return check(
            args.file,
            seeds=args.seeds,
            initializer_seeds=args.initializer_seeds,
            run_timeout_s=args.run_timeout_s or RUN_TIMEOUT_S,
            progress=tell,
            seed_done=seed_done,
            margin_seeds=args.margin_seeds,
            **({} if args.testbed_models is None else {'testbed_models': args.testbed_models}),
        )


def preflight_view(report: CheckReport) -> View:
    """The report; exit 0 when the file passes, 1 when not."""
    data = {'file': report.path, 'passed': report.passed, 'robots': report.robots}
    data |= {'declare_duration_s': report.declare_duration_s, 'problem': report.declaration_problem or None}
    data['runs'] = [_run_data(run) for run in report.runs]
    data['stress_runs'] = [_run_data(run) for run in report.stress_runs]
    data['margins'] = [margin.to_json() for margin in report.margins]
    data['delay_margin'] = None if report.delay_margin is None else report.delay_margin.to_json()
    data['margin_runs'] = [_run_data(run) for run in report.margin_runs]
    return View(tuple(check_lines(report)), data, EXIT_OK if report.passed else EXIT_FAILED)


RUN_WIDTH = 23
"""The run column: 'bundled seed 0 fitted:2' fits."""


def check_lines(report: CheckReport) -> list[str]:
    """A preflight's report in lines: imports, one row per run (the simulator's counts), every problem found, the
    declaration, the verdict."""
    lines = [f'submission {report.path}']
    if report.disallowed_imports:
        return [*lines, f'  FAIL: imports missing on the Robotarium server: {", ".join(report.disallowed_imports)}']
    lines.append('  imports                only the standard library, numpy/scipy/matplotlib/cvxopt and rps: ok')
    lines.append(
        f'  {"run":<{RUN_WIDTH}} {"done":>5} {"too close":>10} {"outside":>8} {"actuator":>9} {"centres [m]":>12} '
        f'{"gap [mm]":>9} {"duration [s]":>13}'
    )
    lines += [_run_line(run) for run in (*report.runs, *report.stress_runs)]
    lines += [f'  FAIL: {problem}' for problem in report.problems]
    lines += [f'  stress ({run.label}): {problem}' for run in report.stress_runs for problem in run.problems]
    lines += [f'  margins                {margin.line()}' for margin in report.margins]
    if report.delay_margin is not None:
        summary, *rungs = report.delay_margin.header_lines()
        lines += [f'  delay margin           {summary}', *(f'                         {rung}' for rung in rungs)]
    declared = report.declaration
    lines.append(
        f'  declare                {report.robots or "?"} robots, '
        + (f'{declared.duration_s} s' if declared else 'no duration')
    )
    if declared:
        lines.append(f'  duration from          {declared.basis()}')
    if report.header_declaration:
        lines.append(f'  header records         {report.header_declaration.duration_s} s')
    lines.append(f'  verdict                {"PASS" if report.passed else "FAIL"}')
    return lines


def _run_line(run: RunReport) -> str:
    """One run of the file as the simulator recorded it, or why there is no record."""
    from robotarium_exp.spec import ROBOTARIUM

    counted, closest, duration = run.counted, run.min_center_distance_m, run.duration_s
    if run.timed_out_s is not None:
        return f'  {run.label:<{RUN_WIDTH}} did not finish in {run.timed_out_s:g} s'
    if counted is None or duration is None:
        return f'  {run.label:<{RUN_WIDTH}} left no record of the simulator (exit {run.returncode})'
    return (
        f'  {run.label:<{RUN_WIDTH}} {"yes" if run.completed else "no":>5} {counted.too_close:>10} {counted.outside:>8} '
        f'{counted.actuator:>9} {"-" if closest is None else f"{closest:.3f}":>12} '
        f'{"-" if closest is None else f"{1000 * (closest - ROBOTARIUM.robot_diameter_m):.0f}":>9} {duration:>13.1f}'
    )


def _run_data(run: RunReport) -> dict[str, object]:
    """One run for ``--json``: the simulator's counts and the verifier's recount of its record."""
    from robotarium_exp.spec import ROBOTARIUM

    counted, recounted, closest = run.counted, run.recounted, run.min_center_distance_m
    return {
        'backend': run.backend,
        'seed': run.seed,
        'ok': run.ok,
        'returncode': run.returncode,
        'completed': run.completed,
        'counted': None if counted is None else counted.to_json(),
        'recounted': None if recounted is None else recounted.to_json(),
        'model': run.model,
        'min_center_distance_m': run.min_center_distance_m,
        'gap_between_bodies_m': None if closest is None else closest - ROBOTARIUM.robot_diameter_m,
        'duration_s': run.duration_s,
        'problems': run.problems,
    }


COMMANDS = (
    Command('submission build', 'write the submission file for a Robotarium scene', build_arguments, build, build_view),
    Command(
        'submission check',
        'preflight a submission on the simulators',
        preflight_arguments,
        preflight,
        preflight_view,
        json=True,
    ),
)
