"""The vtube command line: outputs, exit codes, one-line errors."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import pytest

from vtube.cli import main
from vtube_planning import list_scenes

ROOT = Path(__file__).resolve().parents[1]

GOOD = """
[tube.center]
pieces = [{ kind = "line", length_m = 10.0 }]
[tube.width]
start_m = 2.0
parts = [{ kind = "constant" }]
"""

BAD = {
    'missing_field': GOOD.replace('start_m = 2.0\n', ''),
    'negative_width': GOOD.replace('start_m = 2.0', 'start_m = -2.0'),
    'self_intersecting': GOOD.replace(
        '{ kind = "line", length_m = 10.0 }',
        '{ kind = "line", length_m = 10.0 }, { kind = "arc", radius_m = 3.0, angle_deg = 300.0 }, '
        '{ kind = "line", length_m = 10.0 }',
    ),
    'over_curved': GOOD.replace(
        '{ kind = "line", length_m = 10.0 }', '{ kind = "arc", radius_m = 1.0, angle_deg = 90.0 }'
    ),
    'unknown_key': GOOD + '[swarm]\nspeed = 3\n',
    'not_toml': GOOD + '[swarm\n',
}
BAD_MESSAGES = {
    'missing_field': "missing field 'start_m'",
    'negative_width': 'must be finite and > 0; got -2.0',
    'self_intersecting': 'overlaps itself',
    'over_curved': 'over-curved at l = 0.000 m',
    'unknown_key': "unknown key 'speed' in [swarm]",
    'not_toml': 'not valid TOML',
}


def test_scene_list_prints_every_shipped_scene(capsys) -> None:
    assert main(['scene', 'list']) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == list_scenes()


def test_scene_show_prints_summary_and_writes_figure(tmp_path, capsys) -> None:
    out = tmp_path / 'figs' / 'A.png'
    assert main(['scene', 'show', 'A', '--out', str(out)]) == 0
    text = capsys.readouterr().out
    assert 'length                60.000 m' in text and 'a_rho = 0.5524' in text
    data = out.read_bytes()
    assert data[:8] == b'\x89PNG\r\n\x1a\n' and len(data) > 20_000


def test_scene_show_accepts_a_user_file(tmp_path, capsys) -> None:
    path = tmp_path / 'mine.toml'
    path.write_text(GOOD)
    assert main(['scene', 'show', str(path)]) == 0
    assert 'half-width            2.000 .. 2.000 m' in capsys.readouterr().out


@pytest.mark.parametrize('case', sorted(BAD))
def test_bad_scene_gives_exit_2_and_one_error_line(case: str, tmp_path, capsys) -> None:
    path = tmp_path / f'{case}.toml'
    path.write_text(BAD[case])
    assert main(['scene', 'show', str(path), '--out', str(tmp_path / 'x.png')]) == 2
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 1 and lines[0].startswith('error: ') and BAD_MESSAGES[case] in lines[0]
    assert str(path) in lines[0]  # the message names the file
    assert not (tmp_path / 'x.png').exists()


def test_unknown_scene_gives_exit_2(capsys) -> None:
    assert main(['scene', 'show', 'nowhere']) == 2
    assert capsys.readouterr().err.startswith("error: unknown scene 'nowhere'")


def test_console_entry_point_prints_no_traceback(tmp_path) -> None:
    path = tmp_path / 'bad.toml'
    path.write_text(BAD['self_intersecting'])
    result = subprocess.run(
        [sys.executable, '-m', 'vtube', 'scene', 'show', str(path)], capture_output=True, text=True, check=False
    )
    assert result.returncode == 2
    assert result.stderr.startswith('error: ') and 'Traceback' not in result.stderr
    assert len(result.stderr.splitlines()) == 1


def test_plan_writes_plan_file_and_figure(tmp_path, capsys) -> None:
    from vtube_planning.planning.plan import Plan

    assert main(['plan', 'C', '--out', str(tmp_path), '--grid-step', '0.5']) == 0
    text = capsys.readouterr().out
    assert 'certificate           certified' in text and 'min 0.1' in text
    plan = Plan.load(tmp_path / 'plan_C.npz')
    assert plan.scene == 'C' and plan.options.grid_step_m == 0.5 and plan.l_m.size == 121
    assert (tmp_path / 'plan_C.png').read_bytes()[:4] == b'\x89PNG'


def test_plan_reports_uncertified_polynomial_plans(tmp_path, capsys) -> None:
    assert main(['plan', 'A', '--out', str(tmp_path), '--method', 'polynomial']) == 0
    assert 'NOT certified' in capsys.readouterr().out


def test_infeasible_plan_gives_exit_2_naming_constraint_and_arc_length(tmp_path, capsys) -> None:
    path = tmp_path / 'tight.toml'
    path.write_text(
        GOOD.replace(
            '{ kind = "line", length_m = 10.0 }',
            '{ kind = "line", length_m = 5.0 }, { kind = "arc", radius_m = 3.0, angle_deg = 60.0 }',
        )
    )
    assert main(['plan', str(path), '--out', str(tmp_path)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith('error: (p4) is incompatible with (p2) at l = 4.')
    assert not (tmp_path / 'plan_tight.npz').exists()


def test_simulate_prints_metrics_and_writes_log_and_figures(tmp_path, capsys) -> None:
    from vtube_planning.log import read_log

    assert main(['simulate', 'C', '--out', str(tmp_path), '--n', '8', '--seed', '3']) == 0
    text = capsys.readouterr().out
    assert 'N = 8, seed 3' in text and 'passing time' in text and 'density tracking' in text
    arrays, meta = read_log(tmp_path / 'sim_C_planned.npz')
    assert arrays['positions_m'].shape[1:] == (2, 8) and meta['finished'] and meta['scene'] == 'C'
    for suffix in ('snapshots', 'distance', 'tracking'):
        assert (tmp_path / f'sim_C_planned_{suffix}.png').read_bytes()[:4] == b'\x89PNG'


def test_simulate_without_planning(tmp_path, capsys) -> None:
    assert main(['simulate', 'A', '--out', str(tmp_path), '--no-planning', '--n', '6']) == 0
    assert 'without planning' in capsys.readouterr().out
    assert (tmp_path / 'sim_A_unplanned.npz').exists() and not (tmp_path / 'sim_A_unplanned_tracking.png').exists()


def test_simulate_replans_in_flight_and_reports_each_call(tmp_path, capsys) -> None:
    import json

    assert main(['simulate', 'C', '--out', str(tmp_path), '--n', '8', '--replan-every', '1', '--json']) == 0
    captured = capsys.readouterr()
    replans = json.loads(captured.out)['replans']
    made = [call for call in replans if not call['error']]
    assert len(made) >= 5 and all(call['wall_ms'] > 0 and call['step'] % 50 == 0 for call in replans)
    assert f'every 1 s: {len(made)} replans, median ' in captured.err
    assert main(['simulate', 'C', '--out', str(tmp_path), '--no-planning', '--replan-every', '1']) == 2
    assert 'replanning (replan_every_s) needs a plan' in capsys.readouterr().err


def test_animation_is_a_gif(tmp_path) -> None:
    from vtube_planning.geometry.scene import load_scene
    from vtube_planning.params import ControlParams
    from vtube_planning.plots import animate
    from vtube_planning.swarm.simulate import SimConfig, simulate

    scene = load_scene('A')
    result = simulate(
        scene.tube, replace(scene.swarm, n_robots=4), ControlParams(), plan=None, config=SimConfig(time_limit_s=1.0)
    )
    path = animate(result, scene.tube, tmp_path / 'run.gif', frames=4)
    assert path.read_bytes()[:6] == b'GIF89a'


def test_study_writes_table_json_and_figure(tmp_path, capsys) -> None:
    import json

    assert main(['study', '--out', str(tmp_path), '--scenes', 'A', '--seeds', '1']) == 0
    text = (tmp_path / 'study.md').read_text()
    assert '| A | planning |' in text and 'scene A: holds on the means' in text
    data = json.loads((tmp_path / 'study.json').read_text())
    assert len(data['rows']) == 2 and data['summary'][0]['claim_on_means'] is True
    assert (tmp_path / 'study.png').read_bytes()[:4] == b'\x89PNG'


def test_robotarium_run_prints_the_testbed_verdict(tmp_path, capsys) -> None:
    from vtube_planning.log import read_log

    assert main(['robotarium', 'run', 'robotarium_trapezoid', '--out', str(tmp_path), '--no-initialization']) == 0
    text = capsys.readouterr().out
    assert 'would run on the Robotarium' in text and 'too close (pair-steps) 0' in text
    arrays, meta = read_log(tmp_path / 'experiment_robotarium_trapezoid_planned.npz')
    assert arrays['positions_m'].shape[1:] == (2, 6) and arrays['headings_rad'].shape[1:] == (6,) and meta['completed']
    assert (tmp_path / 'experiment_robotarium_trapezoid_planned.png').read_bytes()[:4] == b'\x89PNG'


@pytest.mark.slow
def test_submission_build_and_check(tmp_path, capsys) -> None:
    out = tmp_path / 'experiment.py'
    build = ['submission', 'build', 'robotarium_trapezoid', '--out', str(out), '--seeds', '1']
    assert main([*build, '--initializer-seeds', '3']) == 0
    text = capsys.readouterr().out
    assert 'verdict                PASS' in text and 'declare                6 robots' in text
    declared = text.split('the header records the declaration: 6 robots, ')[1].split(' s')[0]
    assert f'Declare on the web form: 6 robots and {declared} s' in out.read_text()
    assert main(['submission', 'check', str(out), '--seeds', '1', '--initializer-seeds', '3']) == 0
    assert f'header records         {declared} s' in capsys.readouterr().out
    assert main([*build, '--no-declare']) == 0
    assert 'Declare on the web form: the robot count above' in out.read_text()


def test_submission_build_refuses_a_scene_that_does_not_fit(tmp_path, capsys) -> None:
    assert main(['submission', 'build', 'C', '--out', str(tmp_path / 'x.py')]) == 2
    assert 'does not fit the Robotarium arena' in capsys.readouterr().err
    assert main(['submission', 'check', str(tmp_path / 'missing.py')]) == 2


@pytest.mark.slow
def test_analyze_a_bag_and_the_demo(tmp_path, capsys) -> None:
    import json

    from tests.robotarium_exp.test_analysis import write_bag

    bag = write_bag(tmp_path / 'mocap', 'mcap', 'pose')
    assert main(['analyze', str(bag), '--scene', 'robotarium_trapezoid', '--out', str(tmp_path / 'a')]) == 0
    assert 'analysis of ros bag' in capsys.readouterr().out
    assert json.loads((tmp_path / 'a' / 'metrics.json').read_text())['data']['robots'] == 3
    assert main(['analyze', str(tmp_path / 'nothing'), '--scene', 'robotarium_trapezoid', '--out', str(tmp_path)]) == 2
    assert capsys.readouterr().err.startswith('error: ')
    assert main(['demo', '--out', str(tmp_path / 'demo')]) == 0
    report = (tmp_path / 'demo' / 'report' / 'report.md').read_text()
    assert '| collision pairs | 0 |' in report and 'paths.png' in report


def test_a_plan_file_is_flown_as_given_and_refused_elsewhere(tmp_path, capsys) -> None:
    import numpy as np

    from vtube_planning.planning.plan import Plan

    assert main(['plan', 'robotarium_trapezoid', '--out', str(tmp_path)]) == 0
    plan_file = tmp_path / 'plan_robotarium_trapezoid.npz'
    # a copy of the scene file is the same scene: its plan is accepted, and embedded as it is (not re-planned)
    copy = tmp_path / 'copy.toml'
    copy.write_text((ROOT / 'vtube_planning' / 'scenes' / 'robotarium_trapezoid.toml').read_text(), encoding='utf-8')
    out = tmp_path / 'sub.py'
    build = ['submission', 'build', str(copy), '--plan', str(plan_file), '--out', str(out), '--no-declare']
    assert main(build) == 0
    namespace: dict = {}
    exec(compile(out.read_text(), 'submission', 'exec'), namespace)  # noqa: S102 -- the file just built
    slowness = np.asarray(namespace['DATA']['plan']['slowness_spm'])
    np.testing.assert_allclose(slowness, 1.0 / Plan.load(plan_file).speed_mps, rtol=6e-6)  # six digits
    capsys.readouterr()
    # another tube, another swarm: refused with the reason, exit 2, nothing written
    assert main(['simulate', 'robotarium_curve', '--plan', str(plan_file), '--out', str(tmp_path / 's')]) == 2
    err = capsys.readouterr().err
    assert "error: the plan (made for scene 'robotarium_trapezoid') does not fit scene 'robotarium_curve'" in err
    assert 'a different tube' in err and not (tmp_path / 's').exists()
    assert main(['simulate', 'robotarium_trapezoid', '--n', '5', '--plan', str(plan_file), '--out', str(tmp_path)]) == 2
    assert 'other swarm parameters (n_robots)' in capsys.readouterr().err
    assert main(['robotarium', 'run', 'robotarium_curve', '--plan', str(plan_file), '--out', str(tmp_path)]) == 2
    assert (
        main(
            [
                'analyze',
                str(tmp_path),
                '--scene',
                'robotarium_curve',
                '--plan',
                str(plan_file),
                '--out',
                str(tmp_path / 'a'),
            ]
        )
        == 2
    )


@pytest.mark.slow
def test_robotarium_compare_writes_the_table(tmp_path, capsys) -> None:
    import json

    assert main(['robotarium', 'compare', 'robotarium_curve', '--seeds', '1', '--out', str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert '| measure | planned | unplanned |' in out and '| expansion starts [s] |' in out
    rows = json.loads((tmp_path / 'compare_robotarium_curve.json').read_text())
    assert [row['planned'] for row in rows] == [True, False]
    assert rows[1]['expansion_start_s'] is None and rows[0]['expansion_start_s'] > 0
    assert (tmp_path / 'compare_robotarium_curve.md').read_text().count('\n') == 12


@pytest.mark.parametrize('command', [['study', '--scenes', 'A', '--seeds', '1'], ['ablation', '--seeds', '1']])
def test_an_unwritable_output_folder_is_refused_before_any_run(tmp_path, capsys, command: list[str]) -> None:
    blocker = tmp_path / 'taken'
    blocker.write_text('a file where the folder should go', encoding='utf-8')
    assert main([*command, '--out', str(blocker / 'results')]) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith(f'error: cannot write to {blocker / "results"} (')
    assert 'choose another --out before any run starts.' in captured.err and len(captured.err.splitlines()) == 1
    assert captured.out == ''  # not a single run was flown


def test_version_is_the_package_metadata(capsys) -> None:
    from importlib.metadata import version

    import vtube

    with pytest.raises(SystemExit) as exit_info:
        main(['--version'])
    assert exit_info.value.code == 0 and capsys.readouterr().out.strip() == f'vtube {version("vtube")}'
    assert vtube.__version__ == version('vtube')


def test_help_shows_defaults_and_exit_codes(capsys) -> None:
    with pytest.raises(SystemExit):
        main(['simulate', '--help'])
    text = ' '.join(capsys.readouterr().out.split())
    assert 'seed of the initial formation jitter, >= 0 (default: 0)' in text
    assert 'exit codes: 0 done, every check held; 1 a check or claim failed; 2 bad input' in text
    assert '(default: None)' not in text and '(default: False)' not in text


def test_a_shipped_scene_exported_is_the_same_scene_and_nothing_is_overwritten(tmp_path, capsys) -> None:
    from vtube_planning import load_scene

    path = tmp_path / 'mine.toml'
    assert main(['scene', 'export', 'c', str(path)]) == 0
    mine, shipped = load_scene(path), load_scene('C')
    assert mine.tube.fingerprint() == shipped.tube.fingerprint() and mine.swarm == shipped.swarm
    assert (mine.planning, mine.control) == (shipped.planning, shipped.control)
    path.write_text('edited', encoding='utf-8')
    assert main(['scene', 'export', 'C', str(path)]) == 2
    assert 'exists; give another file name' in capsys.readouterr().err and path.read_text() == 'edited'


@pytest.mark.slow
def test_every_artefact_records_where_it_comes_from(tmp_path, capsys) -> None:
    import hashlib
    import json
    from importlib import resources
    from importlib.metadata import version

    from vtube_planning.log import read_log
    from vtube_planning.planning.plan import Plan

    text = resources.files('vtube_planning.scenes').joinpath('robotarium_trapezoid.toml').read_text(encoding='utf-8')
    digest = hashlib.sha256(text.encode()).hexdigest()

    def recorded(record: dict, seeds: list[int] | None = None) -> None:
        assert record['vtube_version'] == version('vtube') and record['scene_sha256'] == digest
        assert record['utc'].endswith('+00:00') and record['command']
        assert record.get('seeds') == seeds

    assert main(['plan', 'robotarium_trapezoid', '--out', str(tmp_path / 'p')]) == 0
    plan_file = tmp_path / 'p' / 'plan_robotarium_trapezoid.npz'
    recorded(Plan.load(plan_file).provenance)
    assert (tmp_path / 'p' / 'scene_robotarium_trapezoid.toml').read_text(encoding='utf-8') == text
    run = ['robotarium', 'run', 'robotarium_trapezoid', '--no-initialization', '--plan', str(plan_file)]
    assert main([*run, '--out', str(tmp_path / 'r'), '--seed', '3']) == 0
    _, meta = read_log(tmp_path / 'r' / 'experiment_robotarium_trapezoid_planned.npz')
    recorded(meta['provenance'], [3])
    assert meta['provenance']['plan_sha256'] == hashlib.sha256(plan_file.read_bytes()).hexdigest()
    assert (tmp_path / 'r' / 'scene_robotarium_trapezoid.toml').read_text(encoding='utf-8') == text
    log = tmp_path / 'r' / 'experiment_robotarium_trapezoid_planned.npz'
    assert main(['analyze', str(log), '--scene', 'robotarium_trapezoid', '--out', str(tmp_path / 'a')]) == 0
    metrics = json.loads((tmp_path / 'a' / 'metrics.json').read_text())['data']
    recorded(metrics['provenance'])
    assert f'Made by vtube {version("vtube")} on ' in (tmp_path / 'a' / 'report.md').read_text()
    assert (tmp_path / 'a' / 'scene_robotarium_trapezoid.toml').read_text(encoding='utf-8') == text
    assert main(['simulate', 'robotarium_trapezoid', '--out', str(tmp_path / 's'), '--seed', '2']) == 0
    recorded(read_log(tmp_path / 's' / 'sim_robotarium_trapezoid_planned.npz')[1]['provenance'], [2])
    built = tmp_path / 'b' / 'experiment.py'
    assert main(['submission', 'build', 'robotarium_trapezoid', '--out', str(built), '--no-declare']) == 0
    assert f'Generated by vtube {version("vtube")} from scene file' in built.read_text()
    assert f'(sha256 {digest[:16]});' in built.read_text()
    stamp = next(line for line in built.read_text().splitlines() if line.startswith('built on '))
    assert '+00:00 with `' in stamp and 'submission build robotarium_trapezoid' in stamp  # when, and by what command
    capsys.readouterr()


def test_json_output_parses_and_matches_what_is_written(tmp_path, capsys) -> None:
    import json

    from vtube_planning.log import read_log

    out = tmp_path / 's'
    assert main(['simulate', 'robotarium_curve', '--out', str(out), '--json']) == 0
    captured = capsys.readouterr()
    result = json.loads(captured.out)  # stdout holds the JSON object only; the readable lines went to stderr
    assert 'simulation of scene robotarium_curve' in captured.err
    _, meta = read_log(result['log'])
    assert result['metrics'] == json.loads(json.dumps(meta['metrics'])) and result['exit_code'] == 0
    assert main(['analyze', result['log'], '--scene', 'robotarium_curve', '--out', str(tmp_path / 'a'), '--json']) == 0
    analysed = json.loads(capsys.readouterr().out)
    written = json.loads((tmp_path / 'a' / 'metrics.json').read_text())['data']
    assert {k: v for k, v in analysed.items() if k != 'exit_code'} == written
    assert main(['plan', 'Z', '--out', str(tmp_path / 'p'), '--json']) == 2  # an error: nothing on stdout
    assert capsys.readouterr().out == ''


@pytest.mark.slow
def test_simulate_draws_progress_on_a_terminal_only(tmp_path) -> None:
    from tests.terminal import stderr_on_a_pipe, stderr_on_a_terminal

    args = ['simulate', 'robotarium_trapezoid', '--animate']
    code, drawn = stderr_on_a_terminal([*args, '--out', str(tmp_path / 'a')])
    assert code == 0 and b'simulated:' in drawn and b'GIF frames:' in drawn
    quiet = stderr_on_a_terminal([*args, '--out', str(tmp_path / 'b'), '--quiet'])
    assert quiet[0] == 0 and b'simulated:' not in quiet[1]
    assert stderr_on_a_pipe([*args, '--out', str(tmp_path / 'c')]) == (0, '')


@pytest.mark.slow
def test_submission_check_draws_the_initializer_on_a_terminal_only() -> None:
    from tests.terminal import stderr_on_a_pipe, stderr_on_a_terminal

    args = ['submission', 'check', str(ROOT / 'submissions' / 'vtube_robotarium_trapezoid.py'), '--seeds', '1']
    args += ['--initializer-seeds', '4']
    code, drawn = stderr_on_a_terminal(args)
    assert code == 0 and b"V2's initializer:" in drawn and b'/4 [' in drawn  # a bar over the 4 seeds
    assert b'seed 0 (at most 900 s)' in drawn  # what starts is said before it waits
    code, piped = stderr_on_a_pipe(args)
    assert code == 0 and "V2's initializer:" not in piped and 'seed 0 (at most 900 s)' in piped


def test_a_submission_runs_in_this_process_and_leaves_it_as_it_was(tmp_path) -> None:
    import os
    import sys

    from vtube.pipeline import run_on_bundled

    script = tmp_path / 'script.py'
    script.write_text("import os, rps.robotarium\nprint(os.environ['VTUBE_HEADLESS'], rps.robotarium.Robotarium)\n")
    before, cwd, headless = (
        {k for k in sys.modules if k.split('.')[0] == 'rps'},
        os.getcwd(),
        os.getenv('VTUBE_HEADLESS'),
    )
    returned = run_on_bundled(script, tmp_path / 'returned')
    assert returned.ok and "1 <class 'robotarium_exp.rps.robotarium.Robotarium'>" in returned.log.read_text()
    assert {k for k in sys.modules if k.split('.')[0] == 'rps'} == before and os.getcwd() == cwd
    assert os.getenv('VTUBE_HEADLESS') == headless
    script.write_text("raise ValueError('no robots')\n")
    failed = run_on_bundled(script, tmp_path / 'failed')
    assert not failed.ok and 'ValueError: no robots' in failed.log.read_text()
