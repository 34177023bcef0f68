"""The argument types and the checks made before any work."""

from __future__ import annotations

import argparse
import os

import pytest

from vtube.cli.arguments import count, figure_file, parse_sizes, positive, regex, whole, words, writable_folder
from vtube.cli.command import BadInput


def test_whole_numbers_and_counts() -> None:
    assert whole('0') == 0 and whole(' 12 ') == 12 and count('3') == 3
    for text, call, phrase in [('-1', whole, '>= 0'), ('1.5', whole, '>= 0'), ('0', count, '>= 1'), ('x', count, '')]:
        with pytest.raises(argparse.ArgumentTypeError, match=f"'{text}' is not a whole number {phrase}"):
            call(text)


@pytest.mark.parametrize('text', ['0', '-1', 'nan', 'inf', 'x', ''])
def test_positive_refuses_what_is_not_a_finite_number_above_zero(text: str) -> None:
    with pytest.raises(argparse.ArgumentTypeError, match=f"'{text}' is not a number > 0"):
        positive(text)


def test_positive_regex_and_words() -> None:
    assert positive('2.5') == 2.5 and positive('1e-3') == 0.001
    assert regex(r'/(?P<robot>\w+)/pose') == r'/(?P<robot>\w+)/pose'
    with pytest.raises(argparse.ArgumentTypeError, match=r"'\(' is not a regular expression \("):
        regex('(')
    assert words('A,B,C') == ('A', 'B', 'C') and words('A') == ('A',)


def test_sizes_are_whole_numbers_of_at_least_one() -> None:
    assert parse_sizes('20,40,80') == (20, 40, 80)
    for text in ('', '0,20', '20,x', '-3'):
        with pytest.raises(
            BadInput, match=f'--sizes must be comma-separated whole numbers >= 1, like 20,40,80; got {text!r}'
        ):
            parse_sizes(text)
    with pytest.raises(BadInput, match="--n must be comma-separated whole numbers >= 1, like 20,40,80; got '0'"):
        parse_sizes('0', '--n')


def test_an_output_folder_is_checked_without_creating_it(tmp_path) -> None:
    writable_folder(tmp_path / 'new' / 'deeper')  # its nearest existing ancestor is a writable folder
    assert not (tmp_path / 'new').exists()
    blocker = tmp_path / 'file'
    blocker.write_text('x')
    with pytest.raises(BadInput, match=f'cannot write to {blocker / "out"} \\({blocker} is not a folder\\); choose'):
        writable_folder(blocker / 'out')
    if os.geteuid() != 0:  # root may write anywhere
        locked = tmp_path / 'locked'
        locked.mkdir(mode=0o500)
        with pytest.raises(BadInput, match='no permission to write in'):
            writable_folder(locked / 'out')


def test_a_figure_file_must_be_of_a_kind_matplotlib_writes(tmp_path) -> None:
    figure_file(tmp_path / 'a.PNG')
    figure_file(tmp_path / 'a.svg')
    with pytest.raises(BadInput, match=r'cannot write a figure to .*a\.foo: give a file ending in one of .*\.png'):
        figure_file(tmp_path / 'a.foo')
