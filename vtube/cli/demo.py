"""``vtube demo``: the whole pipeline on the bundled simulator, into one report (`vtube.pipeline.demo`)."""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from vtube.cli.analyze import analyze_view
from vtube.cli.arguments import writable_folder
from vtube.cli.command import EXIT_FAILED, EXIT_OK, Command, View
from vtube.cli.plan import plan_view
from vtube.cli.render import progress_bars
from vtube.cli.simulate import simulate_view
from vtube.cli.submission import build_view

if TYPE_CHECKING:
    from vtube.pipeline import DemoStage

RUN_TITLE = 'run the submission on the bundled simulator, as the testbed would, and analyse what it returns'
FLIGHT_MODEL = (
    "  flight model       the paper's single integrator, commands saturated into [v_min, v_max]; the Robotarium run "
    'below flies unicycles through the near-identity map, the barrier certificate and the wheel limits'
)


def demo_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('--out', type=Path, required=True, help='folder for everything the demo writes')


def demo(args: argparse.Namespace) -> Iterator[DemoStage]:
    """The stages, run one by one as they are shown."""
    from vtube import pipeline

    writable_folder(args.out)
    return pipeline.demo(args.out, progress=progress_bars())


def demo_view(stages: Iterator[DemoStage]) -> Iterator[View]:
    """Each stage under its title, as the command of the same name shows it; a stage that fails ends the demo."""
    from vtube.pipeline import Analysed, Planned, Returned, Simulated

    for stage in stages:
        if isinstance(stage, Planned):
            yield _titled('plan', plan_view(stage))
        elif isinstance(stage, Simulated):
            planned = 'with' if stage.result.planned else 'without'
            view = simulate_view(stage)
            yield _titled(f'simulate {planned} planning', replace(view, lines=(*view.lines, FLIGHT_MODEL)))
        elif isinstance(stage, Returned):
            failed = None if stage.ok else f'the submission failed on the bundled simulator; see {stage.log}'
            yield View(('', f'== {RUN_TITLE} =='), exit_code=EXIT_FAILED if failed else EXIT_OK, error=failed)
        elif isinstance(stage, Analysed):
            yield analyze_view(stage)
        else:
            yield _titled('build and check the submission', build_view(stage))


def _titled(title: str, view: View) -> View:
    """A stage's view under its title; a stage that failed stops the demo with exit 1."""
    failed = view.exit_code != EXIT_OK
    error = f'the demo stopped at "{title}"' if failed else None
    return View(('', f'== {title} ==', *view.lines), exit_code=EXIT_FAILED if failed else EXIT_OK, error=error)


COMMAND = Command(
    'demo', 'the whole pipeline on the bundled simulator, into one report', demo_arguments, demo, demo_view
)
