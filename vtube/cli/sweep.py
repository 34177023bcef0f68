"""``vtube robotarium sweep``: scenes x robot counts, each refused with its reason or built and flown on the bundled
simulator with V2's initialization, judged against the bar of issue 31 (`submission.sweep`)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from vtube.cli.arguments import SEEDS_HELP, count, parse_sizes, positive, seeds, writable_folder
from vtube.cli.command import EXIT_FAILED, EXIT_OK, Command, Interrupted, View
from vtube.cli.render import tell

if TYPE_CHECKING:
    from submission.sweep import SweepOutcome

SIZES = '1,2,4,6,8,10,12,15,20'


def sweep_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        'scenes',
        nargs='+',
        metavar='SCENE',
        help='Robotarium scenes: shipped names, .toml files, or map files (generated into OUT/tubes first)',
    )
    parser.add_argument('--n', default=SIZES, help='comma-separated robot counts N')
    parser.add_argument('--seeds', type=seeds, default='3', help=f'initialization {SEEDS_HELP}, per case (default 3)')
    parser.add_argument('--out', type=Path, required=True, help='folder for runs.csv, sweep.md and the built files')
    parser.add_argument('--jobs', type=count, default=1, help='cases run at once, each in its own local process')
    parser.add_argument(
        '--run-timeout', type=positive, default=None, help='seconds one run of a file may take (default 900)'
    )


def sweep(args: argparse.Namespace) -> SweepOutcome:
    """Run what is missing of the sweep into ``--out`` (a rerun resumes it) and write its table."""
    from submission.check import RUN_TIMEOUT_S
    from submission.sweep import sweep as run_sweep
    from vtube_planning.studies.campaign_store import RUNS_FILE

    sizes = parse_sizes(args.n, '--n')
    writable_folder(args.out)

    def told(row: dict[str, object]) -> None:
        tell(f'{row["scene"]} N = {row["n_robots"]}: {row["status"]} {row["error"] or row["reason"]}'.rstrip())

    try:
        return run_sweep(
            args.scenes,
            sizes,
            args.out,
            seeds=args.seeds,
            jobs=args.jobs,
            run_timeout_s=args.run_timeout or RUN_TIMEOUT_S,
            on_row=told,
        )
    except KeyboardInterrupt:
        msg = f'interrupted: every finished case is in {args.out / RUNS_FILE}; run the same command again for the rest.'
        raise Interrupted(msg) from None


def sweep_view(outcome: SweepOutcome) -> View:
    failed = outcome.failed
    head = (
        f'{len(outcome.rows)} cases, {outcome.skipped} already done, {outcome.ran} run now in {outcome.seconds:.0f} s; '
        f'{len(failed)} failed; table {outcome.table}, {outcome.markdown}'
    )
    text = outcome.markdown.read_text(encoding='utf-8').rstrip('\n').splitlines()
    data = {'rows': outcome.rows, 'failed': len(failed), 'table': str(outcome.table)}
    verdict = f'{len(failed)} of {len(outcome.rows)} cases failed' if failed else None
    return View((head, '', *text), data, EXIT_FAILED if failed else EXIT_OK, verdict)


COMMAND = Command(
    'robotarium sweep',
    'scenes x robot counts: refused with a reason, or built, flown and judged',
    sweep_arguments,
    sweep,
    sweep_view,
    json=True,
)
