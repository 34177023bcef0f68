"""``vtube robotarium sweep``: the arguments handed to the sweep, the view and its exit code (the sweep's logic:
``tests/unit/submission/test_sweep.py``; a real case: ``tests/integration/test_sweep.py``)."""

from __future__ import annotations

from pathlib import Path

import pytest

import submission.sweep as sweep_module
from submission.check import RUN_TIMEOUT_S
from submission.sweep import SweepOutcome
from vtube.cli.app import main
from vtube.cli.sweep import sweep_view


def outcome(tmp_path: Path, *statuses: str) -> SweepOutcome:
    markdown = tmp_path / 'sweep.md'
    markdown.write_text('# Robotarium sweep\n\n| scene | N = 1 |\n', encoding='utf-8')
    rows = [{'scene': 's', 'n_robots': k + 1, 'status': status} for k, status in enumerate(statuses)]
    return SweepOutcome(rows, 1, len(rows) - 1, 12.3, tmp_path / 'runs.csv', markdown)


def test_a_sweep_fails_when_a_case_fails_or_raises_and_not_for_a_refusal(tmp_path: Path) -> None:
    passed = sweep_view(outcome(tmp_path, 'PASS', 'refused'))
    assert passed.exit_code == 0 and passed.error is None
    assert passed.lines[0].startswith('2 cases, 1 already done, 1 run now in 12 s; 0 failed; table ')
    assert passed.lines[2:] == ('# Robotarium sweep', '', '| scene | N = 1 |')
    for statuses in (('PASS', 'FAIL'), ('error', 'refused')):
        failed = sweep_view(outcome(tmp_path, *statuses))
        assert failed.exit_code == 1 and failed.error == '1 of 2 cases failed'


def test_the_command_hands_its_arguments_to_the_sweep(tmp_path: Path, monkeypatch, capsys) -> None:
    given = {}

    def fake(scenes, sizes, out, **options):
        given.update(scenes=scenes, sizes=sizes, out=out, **options)
        return outcome(tmp_path, 'PASS')

    monkeypatch.setattr(sweep_module, 'sweep', fake)
    code = main(['robotarium', 'sweep', 'a.toml', 'b', '--n', '1,6', '--seeds', '2', '--out', str(tmp_path / 'o')])
    assert code == 0
    assert (given['scenes'], given['sizes'], given['out']) == (['a.toml', 'b'], (1, 6), tmp_path / 'o')
    assert (given['seeds'], given['jobs'], given['run_timeout_s']) == ((0, 1), 1, RUN_TIMEOUT_S)
    main(['robotarium', 'sweep', 'a.toml', '--seeds', '5-6', '--run-timeout', '30', '--out', str(tmp_path / 'o')])
    assert (given['seeds'], given['run_timeout_s']) == ((5, 6), 30.0)
    assert '# Robotarium sweep' in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(['robotarium', 'sweep', '--help'])
    assert f'(default {RUN_TIMEOUT_S:g})' in ' '.join(capsys.readouterr().out.split())  # the help tells the default


@pytest.mark.parametrize('sizes', ['0', '1,x', ''])
def test_bad_robot_counts_are_refused_before_any_case(tmp_path: Path, sizes: str, capsys) -> None:
    assert main(['robotarium', 'sweep', 'a', '--n', sizes, '--out', str(tmp_path / 'o')]) == 2
    assert '--n must be comma-separated whole numbers >= 1' in capsys.readouterr().err
    assert not (tmp_path / 'o').exists()
