"""The command-line reference page (docs/howto/cli.md), written from the parser the ``vtube`` command itself builds.

``python -m vtube.cli.reference docs/howto/cli.md`` writes it; a test compares the committed page with
[`reference`][vtube.cli.reference.reference], so the page never drifts from the commands. Every command of
`COMMANDS` gets a section: its usage, its help and a table of its arguments, each with its help and default as
``vtube ... --help`` prints them. The text is built from the argparse actions, not from argparse's own help
layout, which changes with the terminal's width and the Python version.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from vtube.cli.app import COMMANDS, GROUPS, HelpFormatter, parser

HEADER = """# Command-line reference

Every `vtube` command with its arguments, as `vtube COMMAND --help` prints them. This page is generated from the
command line's own parser (`python -m vtube.cli.reference docs/howto/cli.md`); a test fails when it differs from
what the code generates.

Every command exits 0 when it is done and every check it made held, 1 when a check or claim failed, 2 on bad input
or refused work (one `error:` line on stderr) and 130 when interrupted. A command with `--json` prints its result
as one JSON object on stdout, and its readable output on stderr.
"""


def reference() -> str:
    """The page's markdown: the header, then one section per command group and command, in the help's order."""
    top = parser()
    parts = [HEADER.rstrip('\n')]
    seen_groups: set[str] = set()
    for words, command in COMMANDS.items():
        first, _, second = words.partition(' ')
        if second and first not in seen_groups:
            seen_groups.add(first)
            parts.append(f'## vtube {first}\n\n{_sentence(GROUPS[first])}')
        level = '###' if second else '##'
        sub = _subparser(top, words.split())
        parts.append(f'{level} vtube {words}\n\n{_sentence(command.help)}\n\n{_usage(words, sub)}\n\n{_table(sub)}')
    return '\n\n'.join(parts) + '\n'


def _subparser(top: argparse.ArgumentParser, words: Sequence[str]) -> argparse.ArgumentParser:
    """The parser of the command named by ``words`` under ``top``."""
    current = top
    for word in words:
        (choices,) = (a.choices for a in current._actions if isinstance(a, argparse._SubParsersAction))
        current = choices[word]
    return current


def _arguments(sub: argparse.ArgumentParser) -> list[argparse.Action]:
    """The command's own arguments: positionals first, then options, without ``--help``."""
    actions = [a for a in sub._actions if not isinstance(a, argparse._HelpAction)]
    return [a for a in actions if not a.option_strings] + [a for a in actions if a.option_strings]


def _usage(words: str, sub: argparse.ArgumentParser) -> str:
    """A usage line: the positionals, then each option in brackets with its metavar."""
    shown = []
    for action in _arguments(sub):
        name = _name(action)
        shown.append(name if not action.option_strings else f'[{name}]')
    return '```text\nvtube ' + ' '.join([words, *shown]) + '\n```'


def _name(action: argparse.Action) -> str:
    """How the argument is written: ``SCENE``, ``--out OUT``, ``--seeds SEEDS [SEEDS ...]``, ``--json``."""
    if not action.option_strings:
        return str(action.metavar or action.dest)
    flag = max(action.option_strings, key=len)
    if action.nargs == 0:
        return flag
    metavar = action.metavar if isinstance(action.metavar, str) else action.dest.upper()
    if action.choices is not None and action.metavar is None:
        metavar = '{' + ','.join(str(c) for c in action.choices) + '}'
    if action.nargs in ('*', '+'):
        return f'{flag} {metavar} [{metavar} ...]'
    return f'{flag} {metavar}'


def _table(sub: argparse.ArgumentParser) -> str:
    """The arguments as a markdown table, the help with its default as ``--help`` shows it."""
    if not _arguments(sub):
        return 'No arguments.'
    formatter = HelpFormatter('vtube')
    rows = ['| argument | what it does |', '|---|---|']
    for action in _arguments(sub):
        text = formatter._get_help_string(action) or ''
        text = text % {**vars(action), 'prog': sub.prog} if '%' in text else text
        aliases = [s for s in action.option_strings if s != max(action.option_strings, key=len)]
        if action.choices is not None and not action.option_strings:
            text = f'{text} (one of: {", ".join(f"`{c}`" for c in action.choices)})'
        if aliases:
            text = f'{text} (also {", ".join(f"`{a}`" for a in aliases)})'
        rows.append(f'| `{_name(action)}` | {_cell(text)} |')
    return '\n'.join(rows)


def _cell(text: str) -> str:
    """``text`` safe in a table cell: its pipes escaped, its lines joined."""
    return ' '.join(text.split()).replace('|', '\\|')


def _sentence(text: str) -> str:
    """``text`` with a capital first letter and a full stop."""
    text = text.strip()
    return text[:1].upper() + text[1:] + ('' if text.endswith('.') else '.')


def main(argv: Sequence[str] | None = None) -> int:
    """Write the page to the file given (or print it): ``python -m vtube.cli.reference docs/howto/cli.md``."""
    args = list(sys.argv[1:] if argv is None else argv)
    if args:
        Path(args[0]).write_text(reference(), encoding='utf-8')
    else:
        sys.stdout.write(reference())
    return 0


if __name__ == '__main__':
    sys.exit(main())
