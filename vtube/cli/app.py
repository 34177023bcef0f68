"""``main``: the parser built from the commands, the dispatch through `COMMANDS`, errors as exit codes.

The everyday loop stays quick: ``vtube --version``, ``vtube --help`` and a refusal by the parser import nothing but
the command modules (their options and help, `Command`); ``main`` builds the options of the one command named on the
command line only (`command_words`), and a command's work (and the packages it needs) is imported when it runs.
``benchmarks/cli_startup.py`` measures it.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from contextlib import AbstractContextManager, nullcontext, redirect_stdout
from typing import Any, NoReturn

from vtube.cli import (
    analyze,
    demo,
    example,
    export,
    plan,
    replay,
    robotarium,
    scene,
    simulate,
    study,
    submission,
    sweep,
    tube,
)
from vtube.cli.command import EXIT_BAD_INPUT, EXIT_INTERRUPTED, BadInput, Command
from vtube.cli.render import error, interrupted, render
from vtube_planning import __version__

COMMANDS: dict[str, Command[Any]] = {
    command.words: command
    for command in (
        *scene.COMMANDS,
        *tube.COMMANDS,
        plan.COMMAND,
        simulate.COMMAND,
        *study.COMMANDS,
        example.COMMAND,
        *robotarium.COMMANDS,
        sweep.COMMAND,
        *submission.COMMANDS,
        analyze.COMMAND,
        export.COMMAND,
        replay.COMMAND,
        demo.COMMAND,
    )
}
"""Every command by its words, in the order the help lists them."""

GROUPS = {
    'scene': 'list and draw scenes',
    'tube': 'generate a tube from an obstacle map, or write a shipped map',
    'campaign': 'run a study declared in a TOML file, anywhere, resumably',
    'robotarium': 'the tube experiment on the bundled Robotarium simulator',
    'submission': 'build and check the single file for the remote Robotarium',
}
"""The help of each first word that has subcommands."""


def refusals() -> tuple[type[BaseException], ...]:
    """Errors that are bad input: one ``error:`` line, exit 2 (imported when a command runs)."""
    from robotarium_exp.errors import RobotariumExpError
    from robotarium_exp.rps.errors import RobotariumError
    from unicycle_mapping.errors import MappingError
    from vtube_planning.errors import VtubeError

    return (VtubeError, RobotariumExpError, RobotariumError, MappingError, OSError, BadInput)


EXIT_CODES = (
    'exit codes: 0 done, every check held; 1 a check or claim failed; 2 bad input or refused work; 130 interrupted.'
)


class HelpFormatter(argparse.HelpFormatter):
    """Help that shows each option's default (when it has one worth showing)."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        text = action.help or ''
        default = action.default
        shown = not (default is None or default is False or default == argparse.SUPPRESS) and '(default' not in text
        return f'{text} (default: %(default)s)' if shown and action.option_strings else text


class Parser(argparse.ArgumentParser):
    """Every vtube (sub)command's parser: defaults in the help, the exit codes below it, and a bad command line told
    in one ``error:`` line, as every other refusal (not argparse's usage block above it)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault('formatter_class', HelpFormatter)
        kwargs.setdefault('epilog', EXIT_CODES)
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_BAD_INPUT, f'{self.prog}: error: {message} (see {self.prog} --help)\n')


def command_words(argv: Sequence[str]) -> str | None:
    """The words of the command ``argv`` names (``'scene show'``), or None when it names none (``--help``, a typo,
    a group without its subcommand: the parser then says what is wrong)."""
    words = [word for word in argv[:2] if not word.startswith('-')][: 2 if argv[:1] and argv[0] in GROUPS else 1]
    if not words or words[0] != argv[0]:
        return None
    found = ' '.join(words)
    return found if found in COMMANDS else None


def parser(words: str | None = None, *, every: bool = True) -> argparse.ArgumentParser:
    """The parser of the commands in `COMMANDS`; a parsed command's words are its ``command``. Each command's
    options are added for the command ``words`` only, or, with ``every``, for all of them (the CLI reference)."""
    top = Parser(
        prog='vtube',
        description='Speed and density planning for a speed-constrained robot swarm through a virtual tube.',
    )
    top.add_argument('--version', action='version', version=f'vtube {__version__}')
    first_words = top.add_subparsers(dest='group', required=True, metavar='COMMAND')
    groups: dict[str, argparse._SubParsersAction[Parser]] = {}
    for command in COMMANDS.values():
        first, _, second = command.words.partition(' ')
        if not second:
            sub = first_words.add_parser(first, help=command.help)
        else:
            if first not in groups:
                group = first_words.add_parser(first, help=GROUPS[first])
                groups[first] = group.add_subparsers(dest='subcommand', required=True, metavar='SUBCOMMAND')
            sub = groups[first].add_parser(second, help=command.help)
        if every or command.words == words:
            if command.json:
                sub.add_argument('--json', action='store_true', help='print the result as one JSON object on stdout')
            command.arguments(sub)
        sub.set_defaults(command=command.words)
    return top


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``vtube`` console script; returns the exit code. With ``--json`` the command's readable
    output goes to stderr and its result, one JSON object, to stdout."""
    given = sys.argv[1:] if argv is None else list(argv)
    args = parser(command_words(given), every=False).parse_args(given)
    command = COMMANDS[args.command]
    as_json = command.json and args.json
    from vtube_planning.provenance import command_line  # what ran, recorded beside every result it writes

    try:
        with command_line(['vtube', *given]):
            with _stdout_to_stderr(as_json):
                result = command.run(args)
            return render(command.view(result), as_json=as_json)
    except refusals() as err:
        error(str(err))
        return EXIT_BAD_INPUT
    except KeyboardInterrupt as stop:
        interrupted(str(stop))
        return EXIT_INTERRUPTED


def _stdout_to_stderr(on: bool) -> AbstractContextManager[object]:
    """While a command runs with ``--json``, whatever it prints goes to stderr: stdout holds the JSON alone."""
    return redirect_stdout(sys.stderr) if on else nullcontext()
