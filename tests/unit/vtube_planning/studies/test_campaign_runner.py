"""Running campaigns from the command line, each run faked: streamed to disk, resumed after an interruption, a
failing run recorded, refused before any run on bad input. The figures of the report are drawn but not rendered
(rendering is checked in tests/integration/test_planning_study.py); runs on local processes and on Dask are in
tests/integration/test_planning_campaign.py."""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import pytest

import vtube_planning.plots
from tests.support.campaigns import SMALL, fake_metrics, write
from vtube.cli import main
from vtube_planning.studies.campaign import run_key
from vtube_planning.studies.campaign_store import RUNS_FILE, read_results


@pytest.fixture(autouse=True)
def unrendered_figures(monkeypatch):
    """save_figure writes an empty file where the PNG would go: the report's figures are drawn, not rendered."""

    def save(fig, path, *, dpi=120):
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(b'')
        return path

    monkeypatch.setattr(vtube_planning.plots, 'save_figure', save)


def test_unreachable_places_are_refused_before_any_run(tmp_path, capsys, fake_runs, monkeypatch) -> None:
    path = write(tmp_path, SMALL)
    argv = ['campaign', 'run', str(path), '--workers', '1']
    unanswered = ['--scheduler', 'tcp://127.0.0.1:9', '--scheduler-timeout', '0.2']
    assert main([*argv, '--out', str(tmp_path / 'out'), *unanswered]) == 2
    err = capsys.readouterr().err
    assert (
        err.startswith('error: no Dask scheduler answered at tcp://127.0.0.1:9 within 0.2 s') and err.count('\n') == 1
    )
    blocker = write(tmp_path, 'a file where the folder should go', 'taken')
    assert main([*argv, '--out', str(blocker / 'results')]) == 2
    assert 'choose another --out before any run starts.' in capsys.readouterr().err
    monkeypatch.setitem(sys.modules, 'distributed', None)  # Dask not installed
    assert main([*argv, '--out', str(tmp_path / 'out'), '--scheduler', 'tcp://127.0.0.1:9']) == 2
    assert 'needs the cluster extra: pip install "vtube[cluster]"' in capsys.readouterr().err
    assert fake_runs[0] == []


def test_an_interrupted_campaign_resumes_with_only_the_missing_runs(tmp_path, capsys, fake_runs) -> None:
    calls, fail = fake_runs
    path, out = write(tmp_path, SMALL), tmp_path / 'out'
    argv = ['campaign', 'run', str(path), '--out', str(out), '--workers', '1']
    fail[6] = KeyboardInterrupt()  # Ctrl-C during the sixth run
    assert main(argv) == 130
    assert 'interrupted: every finished run is in' in capsys.readouterr().err
    campaign, rows, missing = read_results(out)
    assert len(rows) == 5 and missing == 3
    with (out / RUNS_FILE).open('a', encoding='utf-8') as handle:
        handle.write(rows[0]['key'][:8] + ',C,2')  # and a line cut by a hard kill
    first = list(calls[:5])
    calls.clear()
    fail.clear()
    assert main(argv) == 0
    assert '8 runs, 5 already done, 3 run now' in capsys.readouterr().out
    everything = campaign.points()
    assert calls == [p for p in everything if p not in first]  # only the missing ones
    _, rows, missing = read_results(out)
    assert missing == 0 and [r['key'] for r in rows] == [run_key(p, campaign.settings) for p in everything]
    with (out / RUNS_FILE).open(newline='', encoding='utf-8') as handle:
        assert len(list(csv.DictReader(handle))) == 8  # one row per run: the cut line is gone
    for row, point in zip(rows, everything, strict=True):
        assert row['passing_time_s'] == fake_metrics(point)['passing_time_s'] and row['version']


def test_a_ctrl_c_that_python_drops_still_stops_the_campaign_after_that_run(tmp_path, capsys, monkeypatch) -> None:
    """A SIGINT whose KeyboardInterrupt is swallowed where it lands (in a finaliser Python only says "Exception
    ignored"): the run finishes, its row is kept, and the campaign stops there with exit 130."""
    import signal

    import vtube_planning.studies.campaign_runner as runner_module

    calls = []

    def run(point, settings):
        calls.append(point)
        if len(calls) == 3:
            try:
                signal.raise_signal(signal.SIGINT)  # Ctrl-C during the third run...
            except KeyboardInterrupt:
                pass  # ...dropped where it landed
        return fake_metrics(point)

    monkeypatch.setattr(runner_module, 'run_point', run)
    before = signal.getsignal(signal.SIGINT)  # Python's default; ignored in a pytest-xdist worker
    path, out = write(tmp_path, SMALL), tmp_path / 'out'
    assert main(['campaign', 'run', str(path), '--out', str(out), '--workers', '1']) == 130
    assert 'interrupted: every finished run is in' in capsys.readouterr().err
    _, rows, missing = read_results(out)
    assert len(calls) == 3 and len(rows) == 3 and missing == 5
    assert signal.getsignal(signal.SIGINT) is before  # the handler is given back


def test_a_run_that_raises_is_recorded_and_the_others_go_on(tmp_path, capsys, fake_runs) -> None:
    calls, fail = fake_runs
    path, out = write(tmp_path, SMALL), tmp_path / 'out'
    argv = ['campaign', 'run', str(path), '--out', str(out), '--workers', '1']
    fail[3] = ValueError('the plan is\ninfeasible')
    assert main(argv) == 1
    text = capsys.readouterr().out
    assert '8 runs, 0 already done, 8 run now' in text and '1 failed' in text
    assert 'ValueError: the plan is infeasible' in text
    with (out / RUNS_FILE).open(newline='', encoding='utf-8') as handle:
        errors = [row['error'] for row in csv.DictReader(handle)]
    assert errors.count('') == 7 and 'ValueError: the plan is infeasible' in errors
    failed = calls[2]
    calls.clear()
    fail.clear()
    assert main(argv) == 0  # the failed run is tried again, alone
    assert calls == [failed] and read_results(out)[2] == 0


def test_the_file_names_its_folder_and_the_report_shows_the_metrics_kept(tmp_path, capsys, fake_runs) -> None:
    text = 'out = "results"\nmetrics = ["passing_time_s", "min_distance_m", "completed"]\n' + SMALL
    assert main(['campaign', 'run', str(write(tmp_path, text)), '--workers', '1']) == 0
    report = (tmp_path / 'results' / 'report.md').read_text()
    assert '| mode | passing time [s] | min distance [m] | 5 % min distance [m] |\n' in report
    assert '| setting | mode | runs not completed |' in report and 'density error' not in report
    with (tmp_path / 'results' / RUNS_FILE).open(newline='', encoding='utf-8') as handle:
        assert next(csv.reader(handle))[-7:] == [
            'passing_time_s',
            'min_distance_m',
            'completed',
            'wall_s',
            'version',
            'scene_sha256',
            'error',
        ]


def test_a_folder_of_another_campaign_is_refused(tmp_path, capsys, fake_runs) -> None:
    out = tmp_path / 'out'
    assert main(['campaign', 'run', str(write(tmp_path, SMALL)), '--out', str(out), '--workers', '1']) == 0
    other = write(tmp_path, SMALL.replace('[0, 1]', '[0, 1, 2]'), 'other.toml')
    before = (out / RUNS_FILE).read_text()
    capsys.readouterr()
    assert main(['campaign', 'run', str(other), '--out', str(out), '--workers', '1']) == 2
    assert 'holds the results of another campaign' in capsys.readouterr().err
    assert (out / RUNS_FILE).read_text() == before  # nothing lost


def test_families_and_held_out_seeds_change_the_report_not_the_runs(tmp_path, capsys, fake_runs) -> None:
    """A campaign run again with a [families] table and held-out seeds is the same campaign (no run made again):
    its record and its report take the new judging (the family named, the held-out columns)."""
    calls, _ = fake_runs
    out = tmp_path / 'out'
    file = write(tmp_path, SMALL)
    assert main(['campaign', 'run', str(file), '--out', str(out), '--confirm-seeds', '7-8', '--workers', '1']) == 0
    assert len(calls) == 16 and 'held-out seeds' not in (out / 'report.md').read_text()
    family = '[families.latency]\nlatency_steps = [2]\n'
    judged = write(tmp_path, 'confirm_seeds = [7, 8]\nheld_out = true\n' + SMALL + family, 'judged.toml')
    assert main(['campaign', 'run', str(judged), '--out', str(out), '--workers', '1']) == 0
    assert len(calls) == 16  # nothing run again
    report = (out / 'report.md').read_text()
    assert '- latency: 2 claims, 2 pairs each' in report and '(seeds found on; held-out seeds)' in report
    campaign, _, _ = read_results(out)
    assert campaign.held_out and [f.name for f in campaign.families] == ['latency']


def test_two_runs_on_one_folder_lose_no_finished_run_and_write_none_twice(tmp_path, fake_runs, monkeypatch) -> None:
    """Ten times, two runs of one campaign start together on one folder: one holds it, the other is refused (or,
    started after the first ended, finds everything done); the table has every run exactly once."""
    import threading
    import time

    from vtube_planning.studies import campaign_runner
    from vtube_planning.studies.campaign import Campaign, CampaignError

    slow = campaign_runner.run_point
    monkeypatch.setattr(
        campaign_runner, 'run_point', lambda point, settings: (time.sleep(0.002), slow(point, settings))[1]
    )
    campaign = Campaign.from_toml(write(tmp_path, SMALL))
    keys = {run_key(p, campaign.settings) for p in campaign.points()}
    for attempt in range(10):
        out, refused = tmp_path / f'out{attempt}', []

        def run(out=out, refused=refused) -> None:
            try:
                campaign_runner.run_campaign(campaign, out, progress=False)
            except CampaignError as err:
                refused.append(str(err))

        threads = [threading.Thread(target=run) for _ in range(2)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        with (out / RUNS_FILE).open(newline='', encoding='utf-8') as handle:
            written = [row['key'] for row in csv.DictReader(handle)]
        assert sorted(written) == sorted(keys)  # every run once: none lost, none twice
        assert all('is being written by another campaign run' in text for text in refused)
