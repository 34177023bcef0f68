"""Campaigns end to end: the same rows on this process, local processes and a Dask cluster; a campaign killed by a
signal resumes where it stopped; progress drawn on a terminal only."""

from __future__ import annotations

import math
import signal
import subprocess
import sys
import time

import pytest

from tests.support.campaigns import SMALL, write
from tests.support.terminal import stderr_on_a_pipe, stderr_on_a_terminal
from vtube_planning.studies.campaign import Campaign
from vtube_planning.studies.campaign_runner import run_campaign
from vtube_planning.studies.campaign_store import RUNS_FILE, read_results


def comparable(rows: list[dict]) -> list[dict]:
    """Rows without their wall time, NaN as None (so that equal rows compare equal)."""
    return [
        {k: None if isinstance(v, float) and math.isnan(v) else v for k, v in row.items() if k != 'wall_s'}
        for row in rows
    ]


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


def test_progress_is_drawn_on_a_terminal_and_not_on_a_pipe(tmp_path) -> None:
    path = write(tmp_path, SMALL.replace('seed = [0, 1]', 'seed = [0]').replace('[0, 2]', '[0]'))
    code, drawn = stderr_on_a_terminal(['campaign', 'run', str(path), '--out', str(tmp_path / 'a'), '--workers', '1'])
    assert code == 0 and b'2/2' in drawn and b'failed=0' in drawn
    assert stderr_on_a_pipe(['campaign', 'run', str(path), '--out', str(tmp_path / 'b'), '--workers', '1']) == (0, '')


def test_a_scheduler_without_workers_is_refused_within_the_timeout() -> None:
    distributed = pytest.importorskip('distributed')
    from vtube_planning.studies.executors import ExecutorError, connect

    refused = pytest.raises(ExecutorError, match='has no worker after 1 s; start one with `dask worker')
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=':0') as cluster, refused:
        connect(cluster.scheduler_address, timeout_s=1.0)  # an error after the timeout, not a silent wait
