"""The one place that writes to the terminal: views as text or JSON, progress on stderr."""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

from vtube.cli.command import EXIT_OK, View

if TYPE_CHECKING:
    from tqdm import tqdm

    from vtube.pipeline import Progress, Tick


def render(views: View | Iterator[View], *, as_json: bool) -> int:
    """Print views as they come and return the exit code: text on stdout (on stderr with ``--json``, whose object
    alone goes to stdout), a view's error on stderr as ``error: ...``; the first view that fails ends it."""
    text = sys.stderr if as_json else sys.stdout
    try:
        for view in (views,) if isinstance(views, View) else views:
            for line in view.lines:
                print(line, file=text)
            if view.error is not None:
                error(view.error)
            if as_json and view.data is not None:
                from vtube_planning.swarm.metrics import strict_json  # numpy's types as JSON's

                data = strict_json(dict(view.data) | {'exit_code': view.exit_code})
                print(json.dumps(data, allow_nan=False))
            if view.exit_code != EXIT_OK:
                return view.exit_code
    except BrokenPipeError:  # the reader went away (``| head``): no more output, and no error about it
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # nor at the interpreter's final flush
        return views.exit_code if isinstance(views, View) else EXIT_PIPE_CLOSED
    return EXIT_OK


EXIT_PIPE_CLOSED = 141
"""A streamed command whose reader closed the pipe before its end (what a shell reports for SIGPIPE): its result
was not all read, so neither success nor a failure is claimed."""


def error(text: str) -> None:
    """The one ``error:`` line on stderr, on one line whatever ``text`` holds."""
    print('error: ' + ' '.join(text.split()), file=sys.stderr)


def interrupted(text: str) -> None:
    """What an interruption kept, on stderr."""
    print(text or 'interrupted.', file=sys.stderr)


def progress_bar(what: str, unit: str, *, quiet: bool = False) -> tqdm:
    """A progress bar on stderr, drawn only on a terminal and without ``--quiet``."""
    from tqdm import tqdm

    return tqdm(desc=what, unit=unit, disable=quiet or not sys.stderr.isatty(), file=sys.stderr, leave=False)


def progress_bars(*, quiet: bool = False) -> Progress:
    """The pipeline's progress (`vtube.pipeline.Progress`) as bars on stderr."""

    @contextmanager
    def bars(what: str, unit: str) -> Iterator[Tick]:
        with progress_bar(what, unit, quiet=quiet) as bar:
            yield lambda value: bar.update(value - bar.n)

    return bars


def tell(text: str) -> None:
    """One line on stderr about what starts now."""
    print(f'  ... {text}', file=sys.stderr, flush=True)
