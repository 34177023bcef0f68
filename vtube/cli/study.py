"""``vtube study``, ``ablation`` and ``campaign run|report``: studies run as resumable campaigns, and their reports."""

from __future__ import annotations

import argparse
import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from vtube.cli.arguments import SEEDS_HELP, count, parse_sizes, positive, seeds, whole, words, writable_folder
from vtube.cli.command import EXIT_BAD_INPUT, EXIT_FAILED, EXIT_OK, BadInput, Command, Interrupted, View
from vtube_planning.files import write_atomically

if TYPE_CHECKING:
    from vtube_planning.studies.campaign import Campaign
    from vtube_planning.studies.campaign_runner import Outcome
    from vtube_planning.studies.campaign_verify import Verification


@dataclass(frozen=True)
class CampaignRun:
    """A campaign run into a folder: its name, how many runs it has, what was done and where."""

    name: str
    runs: int
    outcome: Outcome
    where: str
    table: Path


@dataclass(frozen=True)
class CampaignReport:
    """A campaign folder's report (its text) and the files written: report.md, then the figures."""

    text: str
    written: tuple[Path, ...]


@dataclass(frozen=True)
class CampaignDone:
    """A campaign run and its report (None: the folder holds no finished run)."""

    run: CampaignRun
    out: Path
    report: CampaignReport | None


@dataclass(frozen=True)
class StudyDone:
    """The paper's comparison run as a campaign: its report and files, and whether every claim held on the means."""

    run: CampaignRun
    text: str
    written: tuple[Path, ...]
    claims_hold: bool


def execution_arguments(parser: argparse.ArgumentParser) -> None:
    """Where a campaign's runs go."""
    parser.add_argument(
        '--workers', type=whole, default=0, help='local processes (default 0: one per core; 1: this process)'
    )
    parser.add_argument(
        '--scheduler', default=None, help='run on this Dask scheduler, tcp://HOST:PORT (vtube[cluster])'
    )
    parser.add_argument(
        '--scheduler-timeout', type=positive, default=10.0, help='seconds to wait for the scheduler (default 10)'
    )
    parser.add_argument('--quiet', action='store_true', help='no progress bar (none is drawn unless on a terminal)')


def execute(campaign: Campaign, out: Path, args: argparse.Namespace) -> CampaignRun:
    """Run what is missing of the campaign on the places of `execution_arguments`: checks the folder and
    connects to the scheduler before any run."""
    import os

    from vtube_planning.studies.campaign_runner import run_campaign
    from vtube_planning.studies.campaign_store import RUNS_FILE
    from vtube_planning.studies.executors import connect

    writable_folder(out)
    points = campaign.points()  # a bad scene fails here, before any run
    client = connect(args.scheduler, args.scheduler_timeout) if args.scheduler else None
    workers = args.workers or os.cpu_count() or 1
    where = f'{workers} local process' + ('es' if workers > 1 else '')
    if client is not None:
        where = f'the Dask cluster at {args.scheduler}'
    try:
        outcome = run_campaign(campaign, out, workers=workers, client=client, progress=False if args.quiet else None)
    except KeyboardInterrupt:
        msg = f'interrupted: every finished run is in {out / RUNS_FILE}; run the same command again to do the rest.'
        raise Interrupted(msg) from None
    finally:
        if client is not None:
            client.close()
    return CampaignRun(campaign.name, len(points), outcome, where, out / RUNS_FILE)


def campaign_run_lines(run: CampaignRun) -> tuple[str, ...]:
    o = run.outcome
    head = (
        f'{run.name}: {run.runs} runs, {o.skipped} already done, {o.ran} run now on {run.where} in {o.seconds:.0f} s, '
        f'{o.failed} failed; table {run.table}'
    )
    failed = (
        f'  failed: {row["key"]} ({row["scene"]}, {row["mode"]}, seed {row["seed"]}): {row["error"]}'
        for row in o.rows
        if row['error']
    )
    return (head, *failed)


def study_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('--out', type=Path, required=True, help='folder for runs.csv, study.md, study.json, study.png')
    parser.add_argument('--seeds', type=seeds, default='5', help=f'{SEEDS_HELP} (default 5: 0-4)')
    parser.add_argument('--scenes', type=words, default='A,B,C,D', help='comma-separated scene names')
    parser.add_argument('--acceleration-limits', action='store_true', help='apply (3), (4) to every robot')
    parser.add_argument(
        '--baselines',
        action='store_true',
        help='add optimized flocking and NMPC on scenes C and D (NMPC: about a minute per run)',
    )
    execution_arguments(parser)


def study(args: argparse.Namespace) -> StudyDone:
    """The paper's comparison with and without planning, as a campaign in ``--out`` (runs.csv, campaign.json; a
    rerun resumes it); writes study.md, study.json and study.png."""
    import json

    from vtube_planning import plots
    from vtube_planning.params import SwarmParams
    from vtube_planning.studies import study_plots
    from vtube_planning.studies.campaign import Campaign
    from vtube_planning.studies.paper_report import study_markdown, summarise
    from vtube_planning.studies.study import BASELINE_MODES, BASELINE_SCENES, MODES
    from vtube_planning.swarm.metrics import strict_json

    out: Path = args.out
    model = 'acceleration limits' if args.acceleration_limits else 'paper'
    common: dict[str, tuple[object, ...]] = {'seed': args.seeds, 'model': (model,)}
    grids = [common | {'scene': args.scenes, 'mode': MODES}]
    compared = tuple(s for s in args.scenes if s in BASELINE_SCENES)
    if args.baselines and compared:
        grids.append(common | {'scene': compared, 'mode': MODES + BASELINE_MODES})
    run = execute(Campaign(tuple(grids), name='study'), out, args)
    rows = [row for row in run.outcome.rows if not row['error']]
    summary = summarise(rows)
    text = study_markdown(summary, list(args.seeds), args.acceleration_limits)
    write_atomically(out / 'study.md', text)
    write_atomically(
        out / 'study.json', json.dumps(strict_json({'rows': rows, 'summary': summary}), indent=1, allow_nan=False)
    )
    figure = plots.save_figure(
        study_plots.study_figure(summary, 2 * SwarmParams().r_p_m, args.seeds), out / 'study.png'
    )
    claims = all(e['claim_on_means'] for e in summary)
    return StudyDone(run, text, (out / 'study.md', out / 'study.json', figure), claims)


def study_view(done: StudyDone) -> View:
    lines = (*campaign_run_lines(done.run), '', done.text, f'written {", ".join(map(str, done.written))}')
    held = done.claims_hold and not done.run.outcome.failed
    return View(lines, exit_code=EXIT_OK if held else EXIT_FAILED)


def ablation_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('--out', type=Path, required=True, help='folder for runs.csv, report.md and the figures')
    parser.add_argument('--scenes', type=words, default='C,D', help='comma-separated scene names')
    parser.add_argument('--sizes', default='20,40,80', help='comma-separated swarm sizes N')
    parser.add_argument('--seeds', type=seeds, default='10', help=f'{SEEDS_HELP} (default 10: 0-9)')
    parser.add_argument(
        '--models',
        type=words,
        default='paper,acceleration limits',
        help="robot models: 'paper' and/or 'acceleration limits'",
    )
    parser.add_argument(
        '--controllers',
        type=words,
        default='law',
        help="'law' (each mode's law alone) and/or 'foresight' (every mode under the foresight, docs/theory.md 11)",
    )
    parser.add_argument(
        '--saturations',
        type=words,
        default='radial,forward',
        help="'radial' (the paper's sat) and/or 'forward' (never backwards)",
    )
    confirm_argument(parser)
    execution_arguments(parser)


def confirm_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        '--confirm-seeds',
        type=seeds,
        default=(),
        help='fresh seeds also run, e.g. 100-109: pooled with the others in the verdicts, unless --held-out',
    )
    parser.add_argument(
        '--held-out',
        action='store_true',
        help='test the --confirm-seeds apart, only on the claims the other seeds found (a replication)',
    )


def ablation(args: argparse.Namespace) -> CampaignDone:
    """The ablation grid as a campaign in ``--out`` (a rerun resumes it), and its report (its families:
    `ABLATION_FAMILIES`)."""
    from vtube_planning.studies.campaign import Campaign
    from vtube_planning.studies.judging import ABLATION_FAMILIES
    from vtube_planning.studies.study import ABLATIONS

    grid = {'scene': args.scenes, 'n_robots': parse_sizes(args.sizes), 'seed': args.seeds}
    grid |= {'model': args.models, 'controller': args.controllers, 'saturation': args.saturations}
    grid |= {'mode': tuple(ABLATIONS)}
    campaign = Campaign(
        (grid,), name='ablation', confirm_seeds=args.confirm_seeds, families=ABLATION_FAMILIES, held_out=args.held_out
    )
    run = execute(campaign, args.out, args)
    return CampaignDone(run, args.out, write_report(args.out))


def campaign_run_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        'file',
        type=Path,
        help='the campaign .toml file (`vtube campaign example faults FILE.toml` writes one to start from)',
    )
    parser.add_argument(
        '--out',
        type=Path,
        default=None,
        help="folder for runs.csv, campaign.json and the report (default: the file's out)",
    )
    confirm_argument(parser)
    execution_arguments(parser)


def campaign_run(args: argparse.Namespace) -> CampaignDone:
    """Run a campaign file into ``--out`` (or the file's ``out``), resuming it, then write its report."""
    from vtube_planning.studies.campaign import Campaign

    campaign = Campaign.from_toml(args.file)
    if args.confirm_seeds:
        campaign = dataclasses.replace(campaign, confirm_seeds=args.confirm_seeds)
    if args.held_out:
        campaign = dataclasses.replace(campaign, held_out=True)
    out = args.out or campaign.out
    if out is None:
        raise BadInput('give the output folder: --out DIR, or out = "DIR" in the campaign file.')
    run = execute(campaign, out, args)
    return CampaignDone(run, out, write_report(out))


def campaign_done_view(done: CampaignDone) -> View:
    """The run, then its report; exit 1 when a run failed (its error is in the table; a rerun tries it again)."""
    lines = campaign_run_lines(done.run)
    if done.report is None:
        return View(lines, exit_code=EXIT_BAD_INPUT, error=_nothing_finished(done.out))
    failed = EXIT_FAILED if done.run.outcome.failed else EXIT_OK
    return View(lines + campaign_report_view(done.report).lines, exit_code=failed)


def write_report(out: Path) -> CampaignReport | None:
    """A campaign folder's tables and figures (report.md, differences.png, verdicts.png, means.png, and
    crossover.png for a crossover campaign), from its table alone (None: it holds no finished run)."""
    from vtube_planning import plots
    from vtube_planning.studies import study_plots
    from vtube_planning.studies.campaign_store import made_by, read_results
    from vtube_planning.studies.crossover import campaign_report_text, is_crossover
    from vtube_planning.studies.study_report import map_differences

    campaign, rows, missing = read_results(out)
    if not rows:
        return None
    text = campaign_report_text(campaign, rows, missing, made_by(out))
    write_atomically(out / 'report.md', text)
    if map_differences(rows, campaign.families):
        differences = study_plots.map_differences_figure(rows, campaign.families)
    else:
        differences = study_plots.paired_differences_figure(rows, campaign.judging)
    figures: tuple[Path, ...] = (
        plots.save_figure(differences, out / 'differences.png'),
        plots.save_figure(study_plots.verdict_matrix_figure(rows, campaign.judging), out / 'verdicts.png'),
        plots.save_figure(study_plots.cell_means_figure(rows), out / 'means.png'),
    )
    if is_crossover(campaign):
        crossover = study_plots.crossover_figure(rows, campaign.judging)
        figures += (plots.save_figure(crossover, out / 'crossover.png'),)
    return CampaignReport(text, (out / 'report.md', *figures))


def campaign_report_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('folder', type=Path, help='the folder a campaign ran into')


def campaign_report(args: argparse.Namespace) -> CampaignReport:
    report = write_report(args.folder)
    if report is None:
        raise BadInput(_nothing_finished(args.folder))
    return report


def campaign_report_view(report: CampaignReport) -> View:
    report_file, *figures = report.written
    return View(('', report.text, f'written {report_file}, {", ".join(map(str, figures))}'))


def campaign_verify_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('folder', type=Path, help='the folder a campaign ran into (the --out of campaign run)')
    parser.add_argument(
        '--runs', type=count, default=None, help='make this many runs again, spread over the table (default: all)'
    )
    parser.add_argument(
        '--workers', type=whole, default=0, help='local processes (default 0: one per core; 1: this process)'
    )


def campaign_verify(args: argparse.Namespace) -> Verification:
    import os

    from vtube_planning.studies.campaign_verify import verify

    return verify(args.folder, runs=args.runs, workers=args.workers or os.cpu_count() or 1)


def campaign_verify_view(found: Verification) -> View:
    """The runs made again and what differs; exit 1 when anything does (the folder is stale: rerun it)."""
    made = ', '.join(f'commit {(m.get("commit") or "?")[:12]}' for m in found.made) or 'no provenance.json'
    lines = [f'made {found.checked} of {found.finished} finished runs again with this code (the runs: {made})']
    lines += [f'  run {d.key}: {d.column} was {d.recorded!r}, is now {d.now!r}' for d in found.differences[:20]]
    if len(found.differences) > 20:
        lines.append(f'  ... and {len(found.differences) - 20} more')
    report = {
        None: 'no report.md',
        True: 'report.md is what the table gives now',
        False: 'report.md differs from what the table gives now',
    }
    lines.append(report[found.report_matches])
    if found.ok:
        return View((*lines, 'the folder holds what this code produces'), exit_code=EXIT_OK)
    error = 'the folder does not hold what this code produces: run the campaign again into a new folder, and its report'
    return View(tuple(lines), exit_code=EXIT_FAILED, error=error)


def _nothing_finished(out: Path) -> str:
    return f'{out} holds no finished run yet; run the campaign first.'


COMMANDS = (
    Command(
        'study',
        "the paper's comparison on scenes A-D with and without planning",
        study_arguments,
        study,
        study_view,
    ),
    Command(
        'ablation',
        'what each part of the method buys: the ablation grid, with intervals',
        ablation_arguments,
        ablation,
        campaign_done_view,
    ),
    Command(
        'campaign run',
        'run (or resume) a campaign and write its report',
        campaign_run_arguments,
        campaign_run,
        campaign_done_view,
    ),
    Command(
        'campaign report',
        "a campaign folder's tables and figures, from runs.csv",
        campaign_report_arguments,
        campaign_report,
        campaign_report_view,
    ),
    Command(
        'campaign verify',
        'whether a campaign folder holds what this code produces: runs made again, report rewritten, compared',
        campaign_verify_arguments,
        campaign_verify,
        campaign_verify_view,
    ),
)
