"""``vtube study``, ``ablation`` and ``campaign run|report``: the grids handed to the campaign, the views, and the
refusals made before any run (a real study: ``tests/integration/test_cli.py``)."""

from __future__ import annotations

from pathlib import Path

import pytest

import vtube.cli.study as study_module
from vtube.cli.app import main
from vtube.cli.command import BadInput
from vtube.cli.study import (
    CampaignDone,
    CampaignReport,
    CampaignRun,
    StudyDone,
    campaign_done_view,
    campaign_report_view,
    campaign_run_lines,
    study_view,
)
from vtube_planning.studies.campaign_runner import Outcome

FAILED_ROW = {'key': 'k1', 'scene': 'C', 'mode': 'planning', 'seed': 2, 'error': 'ValueError: no'}


def campaign_run(failed: int = 0) -> CampaignRun:
    rows = [{'key': 'k0', 'error': ''}, *([FAILED_ROW] * failed)]
    return CampaignRun('study', 4, Outcome(rows, 1, 3, failed, 12.4), '2 local processes', Path('o/runs.csv'))


def test_the_lines_of_a_campaign_run_name_every_failed_run() -> None:
    assert campaign_run_lines(campaign_run()) == (
        'study: 4 runs, 1 already done, 3 run now on 2 local processes in 12 s, 0 failed; table o/runs.csv',
    )
    lines = campaign_run_lines(campaign_run(failed=1))
    assert lines[1] == '  failed: k1 (C, planning, seed 2): ValueError: no'


def test_a_study_fails_when_a_claim_or_a_run_fails() -> None:
    held = study_view(StudyDone(campaign_run(), 'the table', (Path('s.md'), Path('s.png')), True))
    assert held.exit_code == 0 and held.lines[-2:] == ('the table', 'written s.md, s.png')
    assert study_view(StudyDone(campaign_run(), 't', (), False)).exit_code == 1
    assert study_view(StudyDone(campaign_run(failed=1), 't', (), True)).exit_code == 1


def test_a_campaign_with_no_finished_run_is_refused_and_a_report_is_shown() -> None:
    empty = campaign_done_view(CampaignDone(campaign_run(), Path('o'), None))
    assert empty.exit_code == 2 and empty.error == 'o holds no finished run yet; run the campaign first.'
    report = CampaignReport('Campaign: 4 runs.', (Path('o/report.md'), Path('o/d.png'), Path('o/m.png')))
    done = campaign_done_view(CampaignDone(campaign_run(failed=1), Path('o'), report))
    assert done.exit_code == 1 and done.lines[-1] == 'written o/report.md, o/d.png, o/m.png'
    assert campaign_report_view(report).lines == ('', 'Campaign: 4 runs.', 'written o/report.md, o/d.png, o/m.png')


@pytest.fixture
def executed(monkeypatch):
    """``execute`` stubbed: the campaigns it is given, and no run."""
    given = []

    def execute(campaign, out, args):
        given.append((campaign, out, args))
        return campaign_run()

    monkeypatch.setattr(study_module, 'execute', execute)
    monkeypatch.setattr(study_module, 'write_report', lambda out: None)
    return given


def test_the_ablation_grid_from_its_options(tmp_path, executed, capsys) -> None:
    args = ['ablation', '--out', str(tmp_path), '--scenes', 'C', '--sizes', '20,40', '--seeds', '2']
    assert main([*args, '--models', 'paper', '--saturations', 'radial', '--workers', '1']) == 2  # no finished run
    ((campaign, out, options),) = executed
    (grid,) = campaign.grids
    assert out == tmp_path and options.workers == 1 and campaign.name == 'ablation'
    assert (grid['scene'], grid['n_robots'], grid['seed']) == (('C',), (20, 40), (0, 1))
    assert (grid['model'], grid['saturation']) == (('paper',), ('radial',)) and len(grid['mode']) > 1
    assert 'holds no finished run yet' in capsys.readouterr().err


def test_the_ablation_runs_the_seeds_of_a_range_or_a_list(tmp_path, executed) -> None:
    args = ['ablation', '--out', str(tmp_path), '--scenes', 'C', '--sizes', '20', '--workers', '1']
    main([*args, '--seeds', '10-12,20'])
    main([*args, '--seeds', '7,3'])
    assert [campaign.grids[0]['seed'] for campaign, _, _ in executed] == [(10, 11, 12, 20), (7, 3)]


def test_fresh_seeds_to_confirm_reach_the_campaign(tmp_path, executed, capsys) -> None:
    """--confirm-seeds on the ablation and on a campaign file; seeds the grid already runs are refused, named."""
    args = ['ablation', '--out', str(tmp_path), '--scenes', 'C', '--sizes', '20', '--seeds', '0-5', '--workers', '1']
    main([*args, '--confirm-seeds', '100-105'])
    path = tmp_path / 'c.toml'
    path.write_text('[axes]\nscene = ["C"]\nmode = ["planning"]\nseed = 3\n', encoding='utf-8')
    main(['campaign', 'run', str(path), '--out', str(tmp_path / 'c'), '--confirm-seeds', '7,9'])
    assert [campaign.confirm_seeds for campaign, _, _ in executed] == [tuple(range(100, 106)), (7, 9)]
    assert [p.seed for p in executed[1][0].points()] == [0, 1, 2, 7, 9]
    assert main(['campaign', 'run', str(path), '--out', str(tmp_path / 'c'), '--confirm-seeds', '2-4']) == 2
    assert 'confirm_seeds must be fresh seeds' in capsys.readouterr().err


def test_the_study_runs_the_seeds_of_a_range(tmp_path, monkeypatch) -> None:
    given = []

    def execute(campaign, out, args):
        given.append(campaign)
        raise BadInput('stubbed: no run')

    monkeypatch.setattr(study_module, 'execute', execute)
    assert main(['study', '--out', str(tmp_path), '--scenes', 'A', '--seeds', '10-12']) == 2
    assert [grid['seed'] for grid in given[0].grids] == [(10, 11, 12)]


def test_a_campaign_file_without_an_output_folder_is_refused(tmp_path, capsys) -> None:
    path = tmp_path / 'c.toml'
    path.write_text('name = "x"\n[[grid]]\nscene = ["C"]\nmode = ["planning"]\nseed = [0]\n', encoding='utf-8')
    code = main(['campaign', 'run', str(path)])
    assert code == 2 and capsys.readouterr().err.startswith('error: ')


def test_a_report_of_a_folder_without_runs_is_refused(tmp_path, capsys) -> None:
    assert main(['campaign', 'report', str(tmp_path)]) == 2
    assert capsys.readouterr().err.startswith('error: ')


@pytest.mark.parametrize('command', [['study', '--scenes', 'A', '--seeds', '1'], ['ablation', '--seeds', '1']])
def test_an_unwritable_output_folder_is_refused_before_any_run(tmp_path, capsys, command: list[str]) -> None:
    blocker = tmp_path / 'taken'
    blocker.write_text('a file where the folder should go', encoding='utf-8')
    assert main([*command, '--out', str(blocker / 'results')]) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith(f'error: cannot write to {blocker / "results"} (')
    assert 'choose another --out before any run starts.' in captured.err and len(captured.err.splitlines()) == 1
    assert captured.out == ''  # not a single run was flown
