"""Argument types and checks shared by the commands: numbers, patterns, lists, output folders, figure files."""

from __future__ import annotations

import argparse
import math
import os
import re
from pathlib import Path

from vtube.cli.command import BadInput
from vtube_planning.studies.seeds import SEED_MAX, SeedsError, parse_seeds


def whole(text: str) -> int:
    """An argparse type: a whole number >= 0."""
    if not text.strip().isdigit():
        msg = f'{text!r} is not a whole number >= 0'
        raise argparse.ArgumentTypeError(msg)
    return int(text)


def seed(text: str) -> int:
    """An argparse type: a seed, a whole number from 0 to 2**32 - 1."""
    value = whole(text)
    if value > SEED_MAX:
        msg = f'{text!r} is not a seed from 0 to {SEED_MAX} (2**32 - 1)'
        raise argparse.ArgumentTypeError(msg)
    return value


SEEDS_HELP = 'seeds: a count n (0..n-1), a range 10-19 or a list 3,7,11'
"""The help of every ``--seeds`` that names which seeds to run (type `seeds`)."""


def seeds(text: str) -> tuple[int, ...]:
    """An argparse type: which seeds to run, in the order given (`vtube_planning.studies.seeds.parse_seeds`): a
    count n (seeds 0..n-1), a range ``10-19``, a list ``3,7,11`` or a mix ``0-4,10``."""
    try:
        return parse_seeds(text)
    except SeedsError as err:
        raise argparse.ArgumentTypeError(str(err).rstrip('.')) from err


def count(text: str) -> int:
    """An argparse type: a whole number >= 1."""
    value = whole(text)
    if value < 1:
        msg = f'{text!r} is not a whole number >= 1'
        raise argparse.ArgumentTypeError(msg)
    return value


def testbed_model_name(text: str) -> str:
    """An argparse type: a testbed model's name (``ideal``, ``fitted``, ``fitted:K``), checked."""
    from robotarium_exp.rps.testbed_model import testbed_model

    try:
        testbed_model(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from err
    return text


def positive(text: str) -> float:
    """An argparse type: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        msg = f'{text!r} is not a number > 0'
        raise argparse.ArgumentTypeError(msg)
    return value


def regex(text: str) -> str:
    """An argparse type: a regular expression Python can compile."""
    try:
        re.compile(text)
    except re.error as err:
        msg = f'{text!r} is not a regular expression ({err})'
        raise argparse.ArgumentTypeError(msg) from err
    return text


def bag_arguments(parser: argparse.ArgumentParser) -> None:
    """The options that say which of a bag's topics and frames are robots (``vtube analyze``, ``vtube replay``)."""
    parser.add_argument('--topic', action='append', default=None, dest='topics', help='bag topic(s) to read')
    parser.add_argument(
        '--topic-pattern', type=regex, default=None, help='regex with a (?P<robot>...) group for bag topics'
    )
    parser.add_argument(
        '--frame-pattern', type=regex, default=None, help='regex with a (?P<robot>...) group for /tf child frames'
    )
    parser.add_argument(
        '--world-frame', default=None, help='reference frame of the robots (/tf parent, header.frame_id)'
    )


def words(text: str) -> tuple[str, ...]:
    """A comma-separated list of names, none of them empty."""
    names = tuple(part.strip() for part in text.split(','))
    if not all(names):
        msg = f'{text!r} holds an empty name; give names separated by commas, like A,B'
        raise argparse.ArgumentTypeError(msg)
    return names


def parse_sizes(text: str, option: str = '--sizes') -> tuple[int, ...]:
    """A comma-separated list of swarm sizes >= 1 given to ``option`` (checked after parsing: a refusal is one
    ``error:`` line)."""
    try:
        values = tuple(int(part) for part in text.split(','))
    except ValueError:
        values = ()
    if not values or min(values) < 1:
        msg = f'{option} must be comma-separated whole numbers >= 1, like 20,40,80; got {text!r}.'
        raise BadInput(msg)
    return values


def writable_folder(out: Path) -> None:
    """Refuse, before any work and without creating anything, an output folder that cannot be created or written:
    its nearest existing ancestor must be a folder this process may write in."""
    existing = out
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    problem = None
    if not existing.is_dir():
        problem = f'{existing} is not a folder'
    elif not os.access(existing, os.W_OK | os.X_OK):
        problem = f'no permission to write in {existing}'
    if problem is not None:
        msg = f'cannot write to {out} ({problem}); choose another --out before any run starts.'
        raise BadInput(msg)


def figure_file(out: Path) -> None:
    """Refuse, before any work, a figure file of a kind matplotlib cannot write."""
    from matplotlib.backend_bases import FigureCanvasBase

    kinds = FigureCanvasBase.get_supported_filetypes()
    if out.suffix.lstrip('.').lower() not in kinds:
        msg = (
            f'cannot write a figure to {out}: give a file ending in one of {", ".join("." + k for k in sorted(kinds))}.'
        )
        raise BadInput(msg)
