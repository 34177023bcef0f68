"""A campaign folder checked against the code: runs made again (the simulation faked), report rewritten, compared."""

from __future__ import annotations

import math

import pytest

from tests.support.campaigns import SMALL, fake_metrics, write
from vtube.cli import main
from vtube_planning.studies import campaign_runner
from vtube_planning.studies.campaign import Campaign
from vtube_planning.studies.campaign_runner import run_campaign
from vtube_planning.studies.campaign_store import made_by, read_results
from vtube_planning.studies.campaign_verify import _same, verify
from vtube_planning.studies.study_report import report_text


@pytest.fixture
def folder(tmp_path, fake_runs):
    """SMALL run into a folder with its report, as `vtube campaign run` leaves it."""
    campaign = Campaign.from_toml(write(tmp_path, SMALL))
    out = tmp_path / 'out'
    run_campaign(campaign, out, progress=False)
    _, rows, missing = read_results(out)
    (out / 'report.md').write_text(
        report_text(campaign.name, rows, missing, campaign.judging, made_by(out)), encoding='utf-8'
    )
    return out


def test_a_folder_made_by_this_code_verifies(folder, fake_runs) -> None:
    calls, _ = fake_runs
    found = verify(folder, workers=1)
    assert found.ok and (found.checked, found.finished) == (8, 8) and found.report_matches is True
    assert len(calls) == 16  # each run made twice: by the campaign, then again
    (made,) = found.made
    assert made['to_run'] == 8 and made['done_before'] == 0 and 'commit' in made and made['command']
    assert '- 8 runs made by `' in (folder / 'report.md').read_text(encoding='utf-8')


def test_what_the_code_gives_otherwise_now_is_named(folder, monkeypatch) -> None:
    """Seed 1 now passes 0.5 s later: its four runs differ, in passing time only; a sample of two runs checks
    the first and the last; an edited report is caught."""

    def changed(point, settings):
        return fake_metrics(point) | ({'passing_time_s': 10.5 + point.latency_steps} if point.seed == 1 else {})

    monkeypatch.setattr(campaign_runner, 'run_point', changed)
    found = verify(folder, workers=1)
    assert not found.ok and {d.column for d in found.differences} == {'passing_time_s'}
    assert len(found.differences) == 4 and {(d.recorded, d.now) for d in found.differences} == {
        (11.0, 10.5),
        (13.0, 12.5),
    }
    sample = verify(folder, runs=2, workers=1)
    assert sample.checked == 2 and len(sample.differences) == 1  # of the first (seed 0) and last (seed 1) runs
    (folder / 'report.md').write_text('edited by hand\n', encoding='utf-8')
    assert verify(folder, runs=1, workers=1).report_matches is False


def test_the_command_exits_1_on_a_stale_folder(folder, capsys, monkeypatch) -> None:
    assert main(['campaign', 'verify', str(folder), '--workers', '1']) == 0
    assert 'the folder holds what this code produces' in capsys.readouterr().out
    monkeypatch.setattr(campaign_runner, 'run_point', lambda p, s: fake_metrics(p) | {'collision_pairs': 9})
    assert main(['campaign', 'verify', str(folder), '--runs', '3', '--workers', '1']) == 1
    captured = capsys.readouterr()
    assert 'collision_pairs was 0, is now 9' in captured.out and 'does not hold what this code produces' in captured.err


def test_values_agree_to_the_precision_a_table_holds() -> None:
    assert _same(0.1 + 0.2, 0.3, float) and not _same(1.0, 1.0 + 1e-8, float)
    assert _same(math.nan, math.nan, float) and not _same(math.nan, 1.0, float)
    assert _same(3, 3.0, int) and not _same(True, False, bool) and _same('', '', float)
