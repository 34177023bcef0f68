"""Seeds as people type them: counts, ranges, lists and mixes read, refused with the fix, and written back."""

from __future__ import annotations

import pytest

from vtube_planning.studies.seeds import MOST_SEEDS, SEED_MAX, SeedsError, parse_seeds, seeds_text


@pytest.mark.parametrize(
    ('text', 'seeds'),
    [
        ('3', (0, 1, 2)),  # a bare count keeps its old meaning
        ('1', (0,)),
        ('10-19', tuple(range(10, 20))),
        ('3,7,11', (3, 7, 11)),
        ('0-4,10,20-22', (0, 1, 2, 3, 4, 10, 20, 21, 22)),
        ('20-22,3', (20, 21, 22, 3)),  # in the order given
        ('7-7', (7,)),
        (' 3 , 5 - 6 ', (3, 5, 6)),
        (f'{SEED_MAX - 1}-{SEED_MAX}', (SEED_MAX - 1, SEED_MAX)),
        ('0,1', (0, 1)),
    ],
)
def test_seeds_are_read_in_the_order_given(text: str, seeds: tuple[int, ...]) -> None:
    assert parse_seeds(text) == seeds


@pytest.mark.parametrize(
    ('text', 'phrase'),
    [
        ('', 'no seeds given; give a count n (seeds 0..n-1), a range like 10-19'),
        ('  ', 'no seeds given'),
        ('0', "'0' runs no seed: a bare number is a count, give n >= 1 (seeds 0..n-1), or 0-0 for seed 0 alone"),
        ('-1', "'-1' holds a negative number; seeds are whole numbers from 0 to 4294967295"),
        ('3,-4', "'-4' in '3,-4' is negative"),
        ('-3-5', "'-3-5' is negative"),
        ('19-10', "the range '19-10' runs backwards; write it first to last, like 10-19"),
        ('0-4,3', "seed 3 is given twice in '0-4,3'; name each seed once"),
        ('0-4,2-6', 'seed 2 is given twice'),
        ('abc', "'abc' is not a whole number >= 0; give a count n"),
        ('1.5', "'1.5' is not a whole number >= 0"),
        ('1,x', "'x' in '1,x' is not a whole number"),
        ('\u0663', 'is not a whole number'),  # an Arabic-Indic three: digits are ASCII
        ('4294967296', "'4294967296' is not a seed from 0 to 4294967295 (2**32 - 1); give a smaller one"),
        ('0-4294967296', "'4294967296' in '0-4294967296' is not a seed from 0 to 4294967295"),
        ('3,,4', "'3,,4' has an empty item; give seeds separated by single commas"),
        ('3,', 'has an empty item'),
        ('3-', "the range '3-' has no last seed; write both ends, like 10-19"),
        ('1-2-3', "'1-2-3' is not a range; write a range with one dash"),
        (str(MOST_SEEDS + 1), f'is a count of more than {MOST_SEEDS} seeds; give fewer'),
        (f'0-{SEED_MAX}', f'names more than {MOST_SEEDS} seeds; give fewer'),
    ],
)
def test_bad_seeds_are_refused_naming_the_problem_and_the_fix(text: str, phrase: str) -> None:
    with pytest.raises(SeedsError) as caught:
        parse_seeds(text)
    assert phrase in str(caught.value)
    assert isinstance(caught.value, ValueError)


@pytest.mark.parametrize(
    ('seeds', 'text'),
    [
        (tuple(range(10)), '0-9'),
        ((3, 7, 11), '3,7,11'),
        ((0, 1, 2, 3, 4, 10, 20, 21, 22), '0-4,10,20-22'),
        ((3, 4), '3-4'),
        ((7,), '7-7'),  # a bare 7 would be a count
        ((5, 4, 3), '5,4,3'),
        ((), ''),
    ],
)
def test_seeds_are_written_back_compactly_and_read_back_as_themselves(seeds: tuple[int, ...], text: str) -> None:
    assert seeds_text(seeds) == text
    if seeds:
        assert parse_seeds(text) == seeds
