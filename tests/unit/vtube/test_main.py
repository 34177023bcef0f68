"""``python -m vtube``: ``main`` on the command line's arguments, its return value the exit status."""

from __future__ import annotations

import sys

import pytest


@pytest.mark.parametrize(('argv', 'code'), [(['scene', 'list'], 0), (['scene', 'show', 'nowhere'], 2)])
def test_running_the_package_exits_with_mains_code(monkeypatch, capsys, argv: list[str], code: int) -> None:
    monkeypatch.setattr(sys, 'argv', ['vtube', *argv])
    monkeypatch.delitem(sys.modules, 'vtube.__main__', raising=False)
    with pytest.raises(SystemExit) as stop:
        import vtube.__main__  # noqa: F401 -- running it is the test
    assert stop.value.code == code
    captured = capsys.readouterr()
    assert captured.err.startswith("error: unknown scene 'nowhere'") if code else 'robotarium_curve' in captured.out
