"""Campaigns: declared in TOML, expanded into runs with stable keys, run on local processes or Dask, streamed to
disk, resumed after an interruption, refused before any run on bad input."""

from __future__ import annotations

import csv
import math
import signal
import subprocess
import sys
import time
from importlib import resources
from pathlib import Path

import pytest

from tests.terminal import stderr_on_a_pipe, stderr_on_a_terminal
from vtube.cli import main
from vtube_planning import campaign_runner as campaign_module
from vtube_planning import load_scene
from vtube_planning.campaign import METRICS, Campaign, run_key
from vtube_planning.campaign_runner import run_campaign
from vtube_planning.campaign_store import RUNS_FILE, read_results
from vtube_planning.study import Point, RunSettings

FAULTS = """
name = "faults"
[axes]
scene = ["C", "D"]
mode = ["planning", "no planning"]
seed = 3
pose_noise_m = [0.0, 0.02]
"""
SMALL = """
[axes]
scene = ["C"]
mode = ["planning", "no planning"]
seed = [0, 1]
latency_steps = [0, 2]
"""


def write(folder: Path, text: str, name: str = 'campaign.toml') -> Path:
    path = folder / name
    path.write_text(text, encoding='utf-8')
    return path


def fake_metrics(point: Point) -> dict[str, object]:
    """What the fake run measures: values that name the run, so that a row shows which run wrote it."""
    values = dict.fromkeys(METRICS, 0.5) | {'collision_pairs': point.seed, 'tube_violation_steps': 0}
    return values | {'completed': True, 'passing_time_s': 10.0 + point.seed + point.latency_steps}


@pytest.fixture
def fake_runs(monkeypatch):
    """Replace the simulation with :func:`fake_metrics`; ``calls`` lists the points run; ``fail`` maps a call number
    to the exception it raises."""
    calls: list[Point] = []
    fail: dict[int, BaseException] = {}

    def run(point: Point, settings: RunSettings) -> dict[str, object]:
        calls.append(point)
        if len(calls) in fail:
            raise fail[len(calls)]
        return fake_metrics(point)

    monkeypatch.setattr(campaign_module, 'run_point', run)
    return calls, fail


def test_a_campaign_file_expands_into_runs_with_stable_keys(tmp_path) -> None:
    path = write(tmp_path, FAULTS)
    campaign = Campaign.from_toml(path)
    points = campaign.points()
    assert len(points) == 2 * 2 * 3 * 2
    assert {(p.n_robots, p.saturation) for p in points} == {
        (load_scene(s).swarm.n_robots, load_scene(s).control.saturation) for s in 'CD'
    }  # each scene's own N and saturation where the axes leave them out
    assert [p.seed for p in points[:6]] == [0, 0, 1, 1, 2, 2] and points[0].mode == 'planning'
    keys = [run_key(p, campaign.settings) for p in points]
    assert len(set(keys)) == len(keys)
    assert keys == [run_key(p, campaign.settings) for p in Campaign.from_toml(path).points()]  # stable
    moved = write(tmp_path, FAULTS + '[settings]\nfailure_at = 0.25\n', 'moved.toml')
    assert not set(keys) & {run_key(p, RunSettings(failure_at=0.25)) for p in Campaign.from_toml(moved).points()}
    scene_file = write(tmp_path, resources.files('vtube_planning.scenes').joinpath('C.toml').read_text(), 'mine.toml')
    own = Campaign.from_toml(write(tmp_path, '[axes]\nscene = ["mine.toml"]\n', 'own.toml'))
    mine = load_scene(scene_file)
    assert own.points() == [Point(str(scene_file), n_robots=mine.swarm.n_robots, saturation=mine.control.saturation)]


BAD_CAMPAIGNS = {
    'unknown axis': (FAULTS + 'speed = [1.0]\n', "unknown axis 'speed'; the axes are scene, n_robots"),
    'unknown metric': ('metrics = ["fun"]\n' + FAULTS, "unknown metric 'fun'; choose from passing_time_s"),
    'empty grid': (FAULTS.replace('seed = 3', 'seed = []'), 'axes.seed has no values, so the grid is empty'),
    'unknown mode': (FAULTS.replace('"no planning"', '"fast"'), "axes.mode holds 'fast'; choose from 'planning'"),
    'wrong type': (FAULTS.replace('0.02', '"high"'), "axes.pose_noise_m holds 'high'; its values must be floats"),
    'out of range': (FAULTS.replace('0.02', '-0.1'), 'axes.pose_noise_m holds -0.1; its values must be >= 0.0'),
    'unknown scene': (FAULTS.replace('"D"', '"Z"'), "unknown scene 'Z'; shipped scenes are"),
    'unknown setting': (FAULTS + '[settings]\nspeed = 1\n', "unknown setting 'speed'; the settings are dt_s"),
    'bad setting': (FAULTS + '[settings]\nfailure_at = 2.0\n', 'settings.failure_at must be in [0, 1]'),
    'no scene': ('[axes]\nseed = 2\n', 'a grid names no scene: give axes.scene'),
    'no such robot': (
        FAULTS + 'failure = ["stop"]\n[settings]\nfailure_robot = 20\n',
        'does not exist in a swarm of 20',
    ),
    'not TOML': (FAULTS + '[axes\n', 'not a valid TOML file'),
}


@pytest.mark.parametrize('case', list(BAD_CAMPAIGNS))
def test_a_bad_campaign_is_refused_before_any_run(tmp_path, capsys, fake_runs, case: str) -> None:
    text, message = BAD_CAMPAIGNS[case]
    path = write(tmp_path, text)
    assert main(['campaign', 'run', str(path), '--out', str(tmp_path / 'out'), '--workers', '1']) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith('error: ') and len(captured.err.splitlines()) == 1
    assert message in captured.err and captured.out == ''
    assert fake_runs[0] == [] and not (tmp_path / 'out' / RUNS_FILE).exists()


def test_unreachable_places_are_refused_before_any_run(tmp_path, capsys, fake_runs, monkeypatch) -> None:
    path = write(tmp_path, SMALL)
    argv = ['campaign', 'run', str(path), '--workers', '1']
    unanswered = ['--scheduler', 'tcp://127.0.0.1:9', '--scheduler-timeout', '1']
    assert main([*argv, '--out', str(tmp_path / 'out'), *unanswered]) == 2
    err = capsys.readouterr().err
    assert err.startswith('error: no Dask scheduler answered at tcp://127.0.0.1:9 within 1 s') and err.count('\n') == 1
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
        assert next(csv.reader(handle))[-6:] == [
            'passing_time_s',
            'min_distance_m',
            'completed',
            'wall_s',
            'version',
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


def comparable(rows: list[dict]) -> list[dict]:
    """Rows without their wall time, NaN as None (so that equal rows compare equal)."""
    return [
        {k: None if isinstance(v, float) and math.isnan(v) else v for k, v in row.items() if k != 'wall_s'}
        for row in rows
    ]


@pytest.mark.slow
def test_local_processes_and_a_dask_cluster_give_the_same_rows(tmp_path) -> None:
    distributed = pytest.importorskip('distributed')
    campaign = Campaign.from_toml(write(tmp_path, SMALL.replace('seed = [0, 1]', 'seed = [0]')))
    here = run_campaign(campaign, tmp_path / 'here', workers=1, progress=False)
    local = run_campaign(campaign, tmp_path / 'local', workers=2, progress=False)
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=':0', worker_dashboard_address=':0'
    )
    with cluster, distributed.Client(cluster) as client:
        remote = run_campaign(campaign, tmp_path / 'dask', client=client, progress=False)
    assert here.ran == local.ran == remote.ran == 4 and not here.failed
    assert comparable(here.rows) == comparable(local.rows) == comparable(remote.rows)
    assert len({row['passing_time_s'] for row in here.rows}) == 4  # four different runs


def run_cli(args: list[str], **kwargs) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, '-m', 'vtube', *args], text=True, **kwargs)


@pytest.mark.slow
def test_a_campaign_killed_by_a_signal_resumes_where_it_stopped(tmp_path) -> None:
    path, out = write(tmp_path, SMALL), tmp_path / 'out'
    argv = ['campaign', 'run', str(path), '--out', str(out), '--workers', '1']
    process = run_cli(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    table = out / RUNS_FILE
    deadline = time.monotonic() + 120.0
    while time.monotonic() < deadline and not (table.is_file() and table.read_text().count('\n') >= 3):
        time.sleep(0.05)
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 130 and 'interrupted: every finished run is in' in err
    done = read_results(out)[1]
    assert 2 <= len(done) < 8
    written = set(table.read_text().splitlines())
    again = run_cli([*argv, '--quiet'], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    text, err = again.communicate(timeout=300)
    assert again.returncode == 0, err
    assert f'8 runs, {len(done)} already done, {8 - len(done)} run now' in text
    _, rows, missing = read_results(out)
    assert missing == 0 and len({r['key'] for r in rows}) == 8
    assert written <= set(table.read_text().splitlines())  # the runs done before are kept as they were


@pytest.mark.slow
def test_progress_is_drawn_on_a_terminal_and_not_on_a_pipe(tmp_path) -> None:
    path = write(tmp_path, SMALL.replace('seed = [0, 1]', 'seed = [0]').replace('[0, 2]', '[0]'))
    code, drawn = stderr_on_a_terminal(['campaign', 'run', str(path), '--out', str(tmp_path / 'a'), '--workers', '1'])
    assert code == 0 and b'2/2' in drawn and b'failed=0' in drawn
    assert stderr_on_a_pipe(['campaign', 'run', str(path), '--out', str(tmp_path / 'b'), '--workers', '1']) == (0, '')
