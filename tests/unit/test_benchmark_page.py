"""``python -m benchmarks.page``: a benchmark's page holds its docstring, what made it and its output, verbatim."""

from __future__ import annotations

from pathlib import Path

import pytest

from benchmarks import page


def test_a_page_holds_the_docstring_the_command_and_the_output(tmp_path: Path) -> None:
    printed = '| N | step [ms] |\n|---|---|\n| 20 | 0.51 |\n'
    text = page.page_text('sim_bench', ['--sizes', '20'], printed, 'vtube 0.1.0, commit abc, today, 2 cores')
    first, title = text.split('\n')[:2]
    assert (
        first
        == '<!-- made by python -m benchmarks.page: python -m benchmarks.sim_bench --sizes 20 | vtube 0.1.0, commit abc, today, 2 cores -->'
    )
    assert title.startswith('# sim_bench: Time of one control step')
    assert '```text\n' + printed.rstrip() + '\n```\n' in text
    (tmp_path / 'sim_bench.md').write_text(text)
    index = page.index_text(tmp_path)
    assert '(sim_bench.md) (vtube 0.1.0, commit abc, today, 2 cores)' in index


def test_output_with_a_fence_of_its_own_stays_inside_the_block() -> None:
    text = page.page_text('sim_bench', [], 'before\n```\ninside\n```\nafter', 'made')
    assert text.rstrip().endswith('after\n````') and '````text\nbefore' in text


def test_an_unknown_benchmark_is_refused_with_the_known_ones() -> None:
    with pytest.raises(SystemExit, match='no benchmark .*sim_bench'):
        page.docstring('no_such_bench')
    with pytest.raises(SystemExit, match='no benchmark'):
        page.docstring('page')


def test_a_page_is_written_again_from_what_it_records(tmp_path: Path) -> None:
    """`--rewrite` reads the arguments, the output and the making line back, whatever fence the output needed."""
    for printed in ('| N |\n|---|\n| 20 |', 'a\n```\nb\n```\nc'):
        text = page.page_text('sim_bench', ['--sizes', '20', '200'], printed, 'vtube 0.1.0, commit abc')
        (tmp_path / 'sim_bench.md').write_text(text)
        assert page.recorded(tmp_path / 'sim_bench.md') == (
            ['--sizes', '20', '200'],
            printed,
            'vtube 0.1.0, commit abc',
        )
    assert '\n    python -m benchmarks.sim_bench' in text  # the usage line stays indented: a code block, not links
    (tmp_path / 'hand.md').write_text('# written by hand\n')
    with pytest.raises(SystemExit, match='not written by benchmarks.page'):
        page.recorded(tmp_path / 'hand.md')
