"""What a ``vtube`` command is: its options, the call they feed, and the view of what the call returns."""

from __future__ import annotations

import argparse
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from typing import Generic, TypeVar

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_BAD_INPUT = 2
EXIT_INTERRUPTED = 130

R = TypeVar('R')


@dataclass(frozen=True)
class View:
    """What a result shows: its lines of text, its JSON object (None: no JSON form), its exit code and, when the
    command stopped short, the one line said on stderr as ``error: ...``."""

    lines: tuple[str, ...]
    data: Mapping[str, object] | None = None
    exit_code: int = EXIT_OK
    error: str | None = None


@dataclass(frozen=True)
class Command(Generic[R]):
    """One command: its words (``'scene show'``), its help, its options (``arguments`` adds them to its parser),
    the call they feed (``run``) and the view of its result (``view``: one, or one per stage as each ends);
    ``json``: it offers ``--json``."""

    words: str
    help: str
    arguments: Callable[[argparse.ArgumentParser], None]
    run: Callable[[argparse.Namespace], R]
    view: Callable[[R], View | Iterator[View]]
    json: bool = False


class BadInput(Exception):
    """Input a command refuses before or instead of its work: exit 2 with one ``error:`` line."""


class Interrupted(KeyboardInterrupt):
    """Ctrl-C, with the one line that says what was kept."""
