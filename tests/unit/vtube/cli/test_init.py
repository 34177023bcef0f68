"""The CLI package's exports are the defining objects."""

from __future__ import annotations

import vtube.cli
from vtube.cli.app import main
from vtube.cli.command import Command, View


def test_the_exports_are_the_defining_objects() -> None:
    assert sorted(vtube.cli.__all__) == ['Command', 'View', 'main']
    assert (vtube.cli.main, vtube.cli.Command, vtube.cli.View) == (main, Command, View)
