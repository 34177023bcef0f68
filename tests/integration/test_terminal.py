"""Progress on a real terminal (a pty) and off it (a pipe): one real process per kind, on the cheapest command
that draws it. What is drawn, and when, is decided in :mod:`vtube.cli.render`, tested against fake streams in
``tests/unit/vtube/cli/test_render.py``."""

from __future__ import annotations

from pathlib import Path

from tests.support.scenes import LINE_SCENE
from tests.support.terminal import stderr_on_a_terminal

from .test_preflight import silent_files


def test_simulate_draws_its_progress_on_a_terminal(tmp_path: Path) -> None:
    """Off a terminal nothing is drawn: ``test_cli.py::test_simulate_prints_metrics_and_writes_log_and_figures``."""
    scene = tmp_path / 'line.toml'
    scene.write_text(LINE_SCENE, encoding='utf-8')
    args = ['simulate', str(scene), '--n', '2', '--no-planning']
    code, drawn = stderr_on_a_terminal([*args, '--out', str(tmp_path / 'a')])
    assert code == 0 and b'simulated:' in drawn


def test_submission_check_draws_the_initializer_on_a_terminal(tmp_path: Path) -> None:
    """The pipe's side: ``test_preflight.py::test_a_submission_that_never_ends_or_prints_nothing_is_reported_so``."""
    silent = silent_files(tmp_path)['silent']
    args = ['submission', 'check', str(silent), '--seeds', '1', '--initializer-seeds', '1', '--run-timeout', '30']
    code, drawn = stderr_on_a_terminal(args)
    assert code == 1 and b"V2's initializer:" in drawn and b'/1 [' in drawn  # a bar over the seeds
    assert b'seed 0 (at most 30 s)' in drawn  # what starts is said before it waits
