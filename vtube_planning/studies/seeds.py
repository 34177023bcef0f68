"""Which seeds to run, as people type them: a count, a range, a list, or a mix.

`parse_seeds` reads the syntax every ``--seeds`` option and a campaign file's ``seed = "..."`` share;
`seeds_text` writes seeds back in it, compactly, for reports and headers:

    "10"            seeds 0..9 (a bare count n >= 1: seeds 0..n-1, what ``--seeds 10`` always meant)
    "10-19"         seeds 10 to 19, both included
    "3,7,11"        seeds 3, 7 and 11
    "0-4,10,20-22"  a mix: 0, 1, 2, 3, 4, 10, 20, 21, 22
    "7-7"           seed 7 alone (a bare "7" is a count)

Seeds are whole numbers from 0 to 2**32 - 1 (``np.random.seed``, which Robotarium scripts call, takes 32 bits).
"""

from __future__ import annotations

from collections.abc import Sequence

from vtube_planning.errors import VtubeError

SEED_MAX = 2**32 - 1
"""The largest seed."""
MOST_SEEDS = 1_000_000
"""The most seeds one text may name: more is a typo (a million runs take months), not a study to hold in memory."""
SYNTAX = 'a count n (seeds 0..n-1), a range like 10-19, a list like 3,7,11, or a mix like 0-4,10'


class SeedsError(VtubeError, ValueError):
    """Seeds that cannot be read: empty, negative, beyond 32 bits, a range backwards, a seed given twice."""


def parse_seeds(text: str) -> tuple[int, ...]:
    """The seeds ``text`` names (the module's syntax), in the order given: ``"20-22,3"`` is (20, 21, 22, 3).

    Raises `SeedsError` naming what is wrong and how to write it instead."""
    items = [item.strip() for item in text.split(',')]
    if not text.strip():
        msg = f'no seeds given; give {SYNTAX}.'
        raise SeedsError(msg)
    if len(items) == 1 and '-' not in items[0].lstrip('-'):
        return _count(items[0], text)
    seeds: list[int] = []
    seen: set[int] = set()
    for item in items:
        first, last = _range(item, text)
        if len(seeds) + last - first + 1 > MOST_SEEDS:
            msg = f'{text!r} names more than {MOST_SEEDS} seeds; give fewer.'
            raise SeedsError(msg)
        for seed in range(first, last + 1):
            if seed in seen:
                msg = f'seed {seed} is given twice in {text!r}; name each seed once.'
                raise SeedsError(msg)
            seen.add(seed)
            seeds.append(seed)
    return tuple(seeds)


def seeds_text(seeds: Sequence[int]) -> str:
    """``seeds`` written back compactly in the module's syntax, in their order: runs of two or more consecutive
    seeds as ranges (``0-9``), the others listed (``3,7,11``); a single seed alone as ``7-7``, since a bare ``7``
    is a count. `parse_seeds` reads it back as ``seeds``; no seeds give ``''``."""
    if len(seeds) == 1:
        return f'{seeds[0]}-{seeds[0]}'
    parts: list[str] = []
    start = 0
    for k in range(1, len(seeds) + 1):
        if k == len(seeds) or seeds[k] != seeds[k - 1] + 1:
            first, last = seeds[start], seeds[k - 1]
            parts.append(f'{first}-{last}' if last > first else str(first))
            start = k
    return ','.join(parts)


def _count(item: str, text: str) -> tuple[int, ...]:
    """A bare count n: seeds 0..n-1."""
    n = _number(item, text)
    if n < 1:
        msg = f'{text!r} runs no seed: a bare number is a count, give n >= 1 (seeds 0..n-1), or 0-0 for seed 0 alone.'
        raise SeedsError(msg)
    if n > MOST_SEEDS:
        msg = f'{text!r} is a count of more than {MOST_SEEDS} seeds; give fewer, or a range like 10-19.'
        raise SeedsError(msg)
    return tuple(range(n))


def _range(item: str, text: str) -> tuple[int, int]:
    """One item of a list: a seed ``7`` or a range ``10-19`` (its first and last seeds)."""
    if not item:
        msg = f'{text!r} has an empty item; give seeds separated by single commas, like 3,7,11.'
        raise SeedsError(msg)
    first_text, dash, last_text = item.partition('-')
    if dash and not first_text:
        msg = f'{_where(item, text)} is negative; seeds are whole numbers from 0 to {SEED_MAX} (2**32 - 1).'
        raise SeedsError(msg)
    if dash and not last_text.strip():
        msg = f'the range {_where(item, text)} has no last seed; write both ends, like 10-19.'
        raise SeedsError(msg)
    if '-' in last_text:
        msg = f'{_where(item, text)} is not a range; write a range with one dash, like 10-19.'
        raise SeedsError(msg)
    first = _number(first_text, text)
    last = _number(last_text, text) if dash else first
    if last < first:
        msg = f'the range {_where(item, text)} runs backwards; write it first to last, like {last}-{first}.'
        raise SeedsError(msg)
    return first, last


def _number(part: str, text: str) -> int:
    """A seed in ``text``: a whole number from 0 to SEED_MAX."""
    part = part.strip()
    if not (part.isascii() and part.isdigit()):
        msg = f'{_where(part, text)} is not a whole number >= 0; give {SYNTAX}.'
        if part.startswith('-'):
            msg = f'{text!r} holds a negative number; seeds are whole numbers from 0 to {SEED_MAX} (2**32 - 1).'
        raise SeedsError(msg)
    value = int(part)
    if value > SEED_MAX:
        msg = f'{_where(part, text)} is not a seed from 0 to {SEED_MAX} (2**32 - 1); give a smaller one.'
        raise SeedsError(msg)
    return value


def _where(part: str, text: str) -> str:
    """Part of the text, quoted, and the whole text when it is more."""
    return repr(part) if part == text.strip() else f'{part!r} in {text!r}'
