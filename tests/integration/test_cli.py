"""The vtube command line end to end: real runs written to disk, read back; Ctrl-C through a real process.

Where an assertion does not depend on the whole passage, the simulation is cut short (``SimConfig.time_limit_s``
set under the command); everything else the command does (plan, log, figures, JSON, provenance) runs as it is."""

from __future__ import annotations

import functools
import hashlib
import json
import signal
import subprocess
import sys
import time
from importlib import resources
from importlib.metadata import version
from pathlib import Path

import pytest

import vtube_planning.swarm.simulate as simulate_module
from robotarium_exp.scene import load_scene as robotarium_scene
from tests.support.bags import write_bag
from vtube.cli.app import main
from vtube_planning.log import read_log
from vtube_planning.planning.plan import Plan

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def short_flights(monkeypatch) -> None:
    """Simulations of the commands stop after 6 simulated seconds: before any robot exits, so ``simulate`` exits 1
    (a robot did not pass) after writing everything."""
    monkeypatch.setattr(simulate_module, 'SimConfig', functools.partial(simulate_module.SimConfig, time_limit_s=6.0))


def test_console_entry_point_prints_no_traceback(tmp_path) -> None:
    path = tmp_path / 'bad.toml'
    path.write_text('[tube.center]\npieces = [{ kind = "arc", radius_m = 1.0, angle_deg = 90.0 }]\n')
    result = subprocess.run(
        [sys.executable, '-m', 'vtube', 'scene', 'show', str(path)], capture_output=True, text=True, check=False
    )
    assert result.returncode == 2
    assert result.stderr.startswith('error: ') and 'Traceback' not in result.stderr
    assert len(result.stderr.splitlines()) == 1


@pytest.mark.parametrize('args', [['--version'], ['--help'], ['plan', 'A', '--out', 'x', '--grid-step', '-1']])
def test_the_quick_answers_import_no_numerical_library(args: list[str]) -> None:
    """``vtube --version``, ``--help`` and a refusal by the parser, in a process of their own: nothing of numpy,
    scipy, cvxpy or matplotlib is imported (benchmarks/cli_startup.py times them)."""
    probe = (
        'import sys, runpy\n'
        f'sys.argv = ["vtube", *{args!r}]\n'
        'try:\n    runpy.run_module("vtube", run_name="__main__")\n'
        'except SystemExit:\n    pass\n'
        'heavy = sorted({m.split(".")[0] for m in sys.modules} & {"numpy", "scipy", "cvxpy", "matplotlib"})\n'
        'print("heavy:", heavy, file=sys.stderr)\n'
    )
    done = subprocess.run([sys.executable, '-c', probe], cwd=ROOT, capture_output=True, text=True, check=False)
    assert 'heavy: []' in done.stderr, done.stderr[-2000:]


@pytest.mark.parametrize(('streamed', 'code'), [(False, 1), (True, 141)])
def test_a_reader_that_goes_away_ends_the_output_quietly(streamed: bool, code: int) -> None:
    """``vtube ... | head -1``: no "Broken pipe" error; a single view's own exit code, or a stream's 141."""
    views = 'iter([view])' if streamed else 'view'
    script = (
        'import sys; from vtube.cli.render import render; from vtube.cli.command import View; '
        f'view = View(tuple(str(k) for k in range(400000)), None, 1); sys.exit(render({views}, as_json=False))'
    )
    child = subprocess.Popen([sys.executable, '-c', script], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert child.stdout is not None and child.stdout.readline() == b'0\n'
    child.stdout.close()  # the reader goes away after one line
    _, err = child.communicate(timeout=60)
    assert child.returncode == code and err == b''


def test_simulate_prints_metrics_and_writes_log_and_figures(tmp_path, capsys, short_flights) -> None:
    assert main(['simulate', 'C', '--out', str(tmp_path), '--n', '8', '--seed', '3']) == 1  # cut short
    captured = capsys.readouterr()
    text = captured.out
    assert captured.err == ''  # stderr is no terminal here: no progress bar
    assert 'N = 8, seed 3' in text and 'passing time' in text and 'density tracking' in text
    assert '  passage            FAILED: 8 of 8 robots never passed the exit (no passing time)' in text
    arrays, meta = read_log(tmp_path / 'sim_C_planned.npz')
    assert arrays['positions_m'].shape[1:] == (2, 8) and meta['finished'] and meta['scene'] == 'C'
    for suffix in ('snapshots', 'distance', 'tracking'):
        assert (tmp_path / f'sim_C_planned_{suffix}.png').read_bytes()[:4] == b'\x89PNG'
    assert main(['simulate', 'A', '--out', str(tmp_path), '--no-planning', '--n', '6']) == 1
    assert 'without planning' in capsys.readouterr().out
    assert (tmp_path / 'sim_A_unplanned.npz').exists() and not (tmp_path / 'sim_A_unplanned_tracking.png').exists()


def test_simulate_replans_in_flight_and_reports_each_call(tmp_path, capsys, short_flights) -> None:
    assert main(['simulate', 'C', '--out', str(tmp_path), '--n', '8', '--replan-every', '1', '--json']) == 1
    captured = capsys.readouterr()
    replans = json.loads(captured.out)['replans']
    made = [call for call in replans if not call['error']]
    assert len(made) >= 5 and all(call['wall_ms'] > 0 and call['step'] % 50 == 0 for call in replans)
    assert f'every 1 s: {len(made)} replans, median ' in captured.err


def test_json_output_parses_and_matches_what_is_written(tmp_path, capsys, short_flights) -> None:
    out = tmp_path / 's'
    assert main(['simulate', 'robotarium_curve', '--out', str(out), '--json']) == 1  # cut short
    captured = capsys.readouterr()
    result = json.loads(captured.out)  # stdout holds the JSON object only; the readable lines went to stderr
    assert 'simulation of scene robotarium_curve' in captured.err
    _, meta = read_log(result['log'])
    assert result['metrics'] == json.loads(json.dumps(meta['metrics'])) and result['exit_code'] == 1
    assert result['failures'] == ['6 of 6 robots never passed the exit (no passing time)']
    # a simulation's log is timed from its first row (issue 49): its robots that never passed fail it, as simulate said
    assert main(['analyze', result['log'], '--scene', 'robotarium_curve', '--out', str(tmp_path / 'a'), '--json']) == 1
    analysed = json.loads(capsys.readouterr().out)
    written = json.loads((tmp_path / 'a' / 'metrics.json').read_text())['data']
    assert {k: v for k, v in analysed.items() if k != 'exit_code'} == written


def test_study_writes_table_json_and_figure(tmp_path, capsys) -> None:
    assert main(['study', '--out', str(tmp_path), '--scenes', 'A', '--seeds', '1', '--workers', '1']) == 0
    text = (tmp_path / 'study.md').read_text()
    assert '| A | planning |' in text and 'scene A: holds on the means' in text
    data = json.loads((tmp_path / 'study.json').read_text())
    assert len(data['rows']) == 2 and data['summary'][0]['claim_on_means'] is True
    assert (tmp_path / 'study.png').read_bytes()[:4] == b'\x89PNG'


def test_every_artefact_records_where_it_comes_from(tmp_path, capsys, short_flights) -> None:
    """Plan, Robotarium run (its verdict printed), analysis, simulation and build all record their provenance."""
    text = resources.files('robotarium_exp.scenes').joinpath('robotarium_trapezoid.toml').read_text(encoding='utf-8')
    digest = hashlib.sha256(text.encode()).hexdigest()

    def recorded(record: dict, seeds: list[int] | None = None) -> None:
        assert record['vtube_version'] == version('vtube') and record['scene_sha256'] == digest
        assert record['utc'].endswith('+00:00') and record['command']
        assert record.get('seeds') == seeds

    assert main(['plan', 'robotarium_trapezoid', '--out', str(tmp_path / 'p')]) == 0
    plan_file = tmp_path / 'p' / 'plan_robotarium_trapezoid.npz'
    recorded(Plan.load(plan_file, robotarium_scene('robotarium_trapezoid').tube).provenance)
    assert (tmp_path / 'p' / 'scene_robotarium_trapezoid.toml').read_text(encoding='utf-8') == text
    capsys.readouterr()
    run = ['robotarium', 'run', 'robotarium_trapezoid', '--no-initialization', '--plan', str(plan_file)]
    assert main([*run, '--out', str(tmp_path / 'r'), '--seed', '3']) == 0
    said = capsys.readouterr().out
    assert 'would run on the Robotarium' in said and 'too close (pair-steps) 0' in said
    log = tmp_path / 'r' / 'experiment_robotarium_trapezoid_planned.npz'
    arrays, meta = read_log(log)
    assert arrays['positions_m'].shape[1:] == (2, 6) and arrays['headings_rad'].shape[1:] == (6,) and meta['completed']
    assert (tmp_path / 'r' / 'experiment_robotarium_trapezoid_planned.png').read_bytes()[:4] == b'\x89PNG'
    recorded(meta['provenance'], [3])
    assert meta['provenance']['plan_sha256'] == hashlib.sha256(plan_file.read_bytes()).hexdigest()
    assert (tmp_path / 'r' / 'scene_robotarium_trapezoid.toml').read_text(encoding='utf-8') == text
    assert main(['analyze', str(log), '--scene', 'robotarium_trapezoid', '--out', str(tmp_path / 'a')]) == 0
    metrics = json.loads((tmp_path / 'a' / 'metrics.json').read_text())['data']
    recorded(metrics['provenance'])
    assert f'Made by vtube {version("vtube")} on ' in (tmp_path / 'a' / 'report.md').read_text()
    assert (tmp_path / 'a' / 'scene_robotarium_trapezoid.toml').read_text(encoding='utf-8') == text
    assert main(['simulate', 'robotarium_trapezoid', '--out', str(tmp_path / 's'), '--seed', '2']) == 1  # cut short
    recorded(read_log(tmp_path / 's' / 'sim_robotarium_trapezoid_planned.npz')[1]['provenance'], [2])
    built = tmp_path / 'b' / 'experiment.py'
    assert main(['submission', 'build', 'robotarium_trapezoid', '--out', str(built), '--no-declare']) == 0
    assert f'Generated by vtube {version("vtube")} from scene file' in built.read_text()
    assert f'(sha256 {digest[:16]});' in built.read_text()
    stamp = next(line for line in built.read_text().splitlines() if line.startswith('built on '))
    assert '+00:00 with `' in stamp and 'submission build robotarium_trapezoid' in stamp  # when, and by what command
    capsys.readouterr()


NARROW_SCENE = """
[tube.center]
start_xy_m = [-1.0, 0.0]
pieces = [{ kind = "line", length_m = 2.0 }]
[tube.width]
start_m = 0.3
parts = [{ kind = "constant", length_m = 0.8 }, { kind = "linear", length_m = 0.3, to_m = 0.05 }, { kind = "constant" }]
[robotarium]
n_robots = 2
"""
"""Two robots that start abreast where the tube fits the Robotarium, then would pass through 0.9 m of tube 0.10 m
wide: narrower than a body (0.11 m), let alone the safety filter's margin to both walls."""


def test_a_robotarium_run_through_a_tube_narrower_than_a_robot_is_refused_up_front(tmp_path, capsys) -> None:
    """Refused before anything is flown (exit 2, one error line naming the place and the fix): flown, its wall rows
    held both robots before the mouth to the step limit, and before them both scraped through, bodies on the walls."""
    scene = tmp_path / 'narrow.toml'
    scene.write_text(NARROW_SCENE, encoding='utf-8')
    run = ['robotarium', 'run', str(scene), '--no-planning', '--no-initialization', '--out', str(tmp_path)]
    assert main(run) == 2
    error = capsys.readouterr().err.strip()
    assert error.count('\n') == 0 and error.startswith('error:')
    assert 'the tube narrows to 0.10 m at l = 1.10 m, under the 0.18 m' in error and 'widen it' in error
    assert not list(tmp_path.glob('experiment_*'))


def test_analyze_a_bag(tmp_path, capsys) -> None:
    bag = write_bag(tmp_path / 'mocap', 'mcap', 'pose')
    assert main(['analyze', str(bag), '--scene', 'robotarium_trapezoid', '--out', str(tmp_path / 'a')]) == 0
    assert 'analysis of ros bag' in capsys.readouterr().out
    assert json.loads((tmp_path / 'a' / 'metrics.json').read_text())['data']['robots'] == 3


AT_A_TERMINAL = (
    'import signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler); from vtube.cli import main; '
    'sys.exit(main())'
)
"""``vtube`` as at a terminal, where Ctrl-C interrupts (a test run started as a background job ignores SIGINT, and
its children would inherit that)."""


def test_ctrl_c_keeps_the_finished_log_and_says_so_in_one_line(tmp_path) -> None:
    from robotarium_exp.scene import load_scene
    from vtube_planning.swarm.simulate import SimConfig, simulate

    out = tmp_path / 'out'
    out.mkdir()
    log = out / 'sim_A_planned.npz'
    scene = load_scene('A')  # a finished log at the path the command writes to (a short run of its own)
    simulate(scene.tube, scene.swarm, scene.control, plan=None, config=SimConfig(time_limit_s=0.5), log_path=log)
    finished = log.read_bytes()
    process = subprocess.Popen(
        [sys.executable, '-c', AT_A_TERMINAL, 'simulate', 'A', '--out', str(out), '--seed', '1'],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    partial = out / 'sim_A_planned.partial.npz'
    deadline = time.monotonic() + 120.0
    while not partial.exists() and time.monotonic() < deadline:  # interrupted mid-run, after its first flush
        time.sleep(0.02)
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 130 and len(err.strip().splitlines()) == 1, err
    assert err.startswith(f'interrupted: the steps flown so far are in {partial};'), err
    assert log.read_bytes() == finished  # the earlier, finished log is intact
    assert partial.stat().st_size > 0  # and the interrupted run's rows are in the partial log
