"""``vtube campaign example``: a campaign file shipped with the package, written where the user is, to run or edit.

The files are package data (``vtube/examples/*.toml``: the README's campaigns), so they exist in an installed
package, which has no ``docs/``.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from vtube.cli.command import BadInput, Command, View
from vtube_planning.files import write_atomically


@dataclass(frozen=True)
class ExampleWritten:
    """A shipped campaign ``name`` written to ``path``."""

    name: str
    path: Path


def campaign_examples() -> dict[str, str]:
    """The shipped campaign files, name -> text."""
    folder = resources.files('vtube') / 'examples'
    return {
        entry.name.removesuffix('.toml'): entry.read_text(encoding='utf-8')
        for entry in sorted(folder.iterdir(), key=lambda entry: entry.name)
        if entry.name.endswith('.toml')
    }


def example_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('name', choices=sorted(campaign_examples()), help='the shipped campaign')
    parser.add_argument('file', type=Path, help='the .toml file to write (must not exist)')


def write_new(path: Path, text: str) -> None:
    """Write a shipped example to ``path``, refusing a file that exists (nothing is overwritten)."""
    if path.exists():
        msg = f'{path} exists; give another file name (nothing was written).'
        raise BadInput(msg)
    write_atomically(path, text)


def example(args: argparse.Namespace) -> ExampleWritten:
    write_new(args.file, campaign_examples()[args.name])
    return ExampleWritten(args.name, args.file)


def example_view(written: ExampleWritten) -> View:
    run = f'vtube campaign run {written.path} --out FOLDER'
    return View((f'campaign {written.name} written to {written.path}; run it with: {run}',))


COMMAND = Command(
    'campaign example',
    "write a shipped campaign's file (the README's campaigns), to run or edit",
    example_arguments,
    example,
    example_view,
)
