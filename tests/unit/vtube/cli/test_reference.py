"""The command-line reference page: generated from the parser, and the committed page is what the code generates."""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import pytest

from vtube.cli.app import COMMANDS, GROUPS
from vtube.cli.reference import main, reference

ROOT = Path(__file__).resolve().parents[4]
PAGE = ROOT / 'docs' / 'howto' / 'cli.md'


def test_the_committed_page_is_what_the_code_generates() -> None:
    assert PAGE.read_text(encoding='utf-8') == reference(), (
        'the CLI changed: regenerate with python -m vtube.cli.reference docs/howto/cli.md'
    )


def test_every_command_and_group_has_a_section() -> None:
    headings = {line.lstrip('#').strip() for line in reference().splitlines() if line.startswith('#')}
    assert {f'vtube {words}' for words in COMMANDS} <= headings
    assert {f'vtube {group}' for group in GROUPS} <= headings


def test_every_option_of_a_command_is_in_its_section() -> None:
    page = reference()
    section = page[page.index('### vtube robotarium run') : page.index('### vtube robotarium compare')]
    for option in ('--plan PLAN', '--no-initialization', '--seed SEED', '--testbed-model', '--json', '`scene`'):
        assert option in section, option
    assert '(default: ideal)' in section  # the help's defaults, as --help shows them
    assert '--help' not in section


def test_a_positional_with_choices_names_them() -> None:
    page = reference()
    section = page[page.index('### vtube campaign example') :]
    assert '(one of: `delay`, `faults`, `replanning`)' in section


def test_the_page_follows_a_changed_parser(monkeypatch: pytest.MonkeyPatch) -> None:
    """A new option shows on the page, so a stale committed page fails the test above."""
    command = COMMANDS['demo']

    def with_extra(sub: argparse.ArgumentParser) -> None:
        command.arguments(sub)
        sub.add_argument('--brand-new', help='an option the page does not have yet')

    monkeypatch.setitem(COMMANDS, 'demo', dataclasses.replace(command, arguments=with_extra))
    assert '| `--brand-new BRAND_NEW` | an option the page does not have yet |' in reference()
    assert '--brand-new' not in PAGE.read_text(encoding='utf-8')


def test_main_writes_the_page_or_prints_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main([str(tmp_path / 'cli.md')]) == 0
    assert (tmp_path / 'cli.md').read_text(encoding='utf-8') == reference()
    assert main([]) == 0
    assert capsys.readouterr().out == reference()
