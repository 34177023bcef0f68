"""The ``vtube`` command line: one module per command group, each declaring its commands (`Command`), and
`main`, which parses, dispatches and renders."""

from vtube.cli.app import main
from vtube.cli.command import Command, View

__all__ = ['Command', 'View', 'main']
