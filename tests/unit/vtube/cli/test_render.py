"""The one writer to the terminal: views as text or JSON, error lines, and progress drawn on a terminal only
(decided against fake streams here; one real pty per kind in ``tests/integration/test_terminal.py``)."""

from __future__ import annotations

import io
import json
import math
import sys

import vtube.cli.render as render_module
from vtube.cli.command import EXIT_FAILED, EXIT_OK, View
from vtube.cli.render import error, interrupted, progress_bar, progress_bars, render, tell


class Terminal(io.StringIO):
    """A stream that says it is a terminal."""

    def isatty(self) -> bool:
        return True


class Pipe(io.StringIO):
    def isatty(self) -> bool:
        return False


def stderr_is(monkeypatch, stream: io.StringIO) -> io.StringIO:
    """``stream`` as stderr for the rest of the test (set in the test: pytest's capture resets it between phases)."""
    monkeypatch.setattr(sys, 'stderr', stream)
    return stream


def test_text_goes_to_stdout_and_the_exit_code_is_the_first_failure(capsys) -> None:
    views = iter(
        [View(('one', 'two')), View(('three',), exit_code=EXIT_FAILED, error='it broke\n  here'), View(('x',))]
    )
    assert render(views, as_json=False) == EXIT_FAILED
    captured = capsys.readouterr()
    assert captured.out == 'one\ntwo\nthree\n'  # the view after the failure is never shown
    assert captured.err == 'error: it broke here\n'  # one line, whatever the text held


def test_json_puts_the_object_alone_on_stdout_and_the_text_on_stderr(capsys) -> None:
    view = View(('readable',), {'value': 1.5, 'bad': math.nan, 'nested': {'inf': math.inf}})
    assert render(view, as_json=True) == EXIT_OK
    captured = capsys.readouterr()
    assert json.loads(captured.out) == {'value': 1.5, 'bad': None, 'nested': {'inf': None}, 'exit_code': 0}
    assert captured.err == 'readable\n'
    assert render(View(('no json form',)), as_json=True) == EXIT_OK  # data None: nothing on stdout
    assert capsys.readouterr().out == ''


def test_a_failing_view_carries_its_exit_code_into_the_json(capsys) -> None:
    assert render(View((), {'passed': False}, exit_code=EXIT_FAILED), as_json=True) == EXIT_FAILED
    assert json.loads(capsys.readouterr().out) == {'passed': False, 'exit_code': EXIT_FAILED}


def test_error_interrupted_and_tell_write_one_line_on_stderr(capsys) -> None:
    error('a\nb')
    interrupted('')
    interrupted('interrupted: kept x')
    tell('running seed 0')
    assert capsys.readouterr() == ('', 'error: a b\ninterrupted.\ninterrupted: kept x\n  ... running seed 0\n')


def test_a_bar_is_drawn_on_a_terminal(monkeypatch) -> None:
    terminal = stderr_is(monkeypatch, Terminal())
    with progress_bar('simulated', 's') as bar:
        bar.reset(total=4)
        bar.update(4)
    drawn = terminal.getvalue()
    assert 'simulated:' in drawn and '/4 [' in drawn


def test_no_bar_off_a_terminal_or_when_quiet(monkeypatch) -> None:
    pipe = stderr_is(monkeypatch, Pipe())
    with progress_bar('simulated', 's') as bar:
        bar.update(3)
    assert pipe.getvalue() == ''
    quiet = stderr_is(monkeypatch, Terminal())
    with progress_bar('simulated', 's', quiet=True) as bar:
        bar.update(3)
    assert quiet.getvalue() == ''


def test_the_pipelines_progress_ticks_move_the_bar_to_the_value(monkeypatch) -> None:
    """A tick says how far the stage has come (not by how much): the bar ends at the last value."""
    terminal = stderr_is(monkeypatch, Terminal())
    made = []

    def kept(*args, **kwargs):
        made.append(progress_bar(*args, **kwargs))
        return made[-1]

    monkeypatch.setattr(render_module, 'progress_bar', kept)
    with progress_bars()('GIF frames', 'frame') as tick:
        for value in (1, 2, 5):
            tick(value)
        assert 'GIF frames:' in terminal.getvalue() and made[0].n == 5
    with progress_bars(quiet=True)('simulated', 's') as tick:
        tick(1.0)
    assert 'simulated' not in terminal.getvalue()
