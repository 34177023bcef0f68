"""``vtube submission build|check``: the views of a build and of a preflight, the initializer's bar, and a plan
file embedded as given (the real preflight: ``tests/integration/test_preflight.py``)."""

from __future__ import annotations

import io
import json
import sys
from pathlib import Path

import numpy as np
import pytest

import submission.check as check_module
from robotarium_exp.initializer import InitializerSample
from robotarium_exp.scene import load_scene
from submission.builder import UNDECLARED, Submission
from submission.check import CheckReport, RunReport
from submission.declaration import FULL_BUILD_INITIALIZER_SEEDS, declare
from vtube import pipeline
from vtube.cli.app import main
from vtube.cli.submission import build_view, check_lines, preflight_view
from vtube_planning.planning.plan import Plan

from ...submission.test_check import record
from ..cli.test_render import Pipe, Terminal

ROOT = Path(__file__).resolve().parents[4]
DECLARED = declare(InitializerSample((20.0, 35.5), ()), experiment_s=61.3)
SUB = Submission('x', 'robotarium_curve', True, 6)


def report(*runs: RunReport, **change) -> CheckReport:
    values = {'runs': runs, 'robots': 6, 'declaration': DECLARED}
    return CheckReport('/f.py', **(values | change))


GOOD = RunReport('bundled', 0, 0, record=record(100), completed=True)


def test_a_passing_preflight_in_lines_and_json() -> None:
    timed_out = RunReport('pypi', None, -1, timed_out_s=3.0)
    lines = check_lines(report(GOOD, header_declaration=DECLARED))
    assert lines[0] == 'submission /f.py' and 'only the standard library' in lines[1]
    assert (
        lines[3] == '  bundled seed 0            yes          0        0         0        0.500       390           3.5'
    )
    assert 'centres [m]' in lines[2] and 'gap [mm]' in lines[2]  # 0.5 m between centres, bodies 0.11 m wide
    assert lines[2].index('done') + 4 == lines[3].index('yes') + 3  # right-aligned columns line up
    assert lines[-4:] == [
        '  declare                6 robots, 100 s',
        f'  duration from          {DECLARED.basis()}',
        '  header records         100 s',
        '  verdict                PASS',
    ]
    failing = check_lines(report(GOOD, timed_out, RunReport('bundled', 1, 1), declaration=None))
    assert f'  {"pypi":<23} did not finish in 3 s' in failing
    assert f'  {"bundled seed 1":<23} left no record of the simulator (exit 1)' in failing
    assert '  FAIL: pypi: did not finish in 3 s (raise --run-timeout if it should)' in failing
    assert failing[-2:] == ['  declare                6 robots, no duration', '  verdict                FAIL']
    imports = check_lines(CheckReport('/f.py', disallowed_imports=('cvxpy', 'torch')))
    assert imports == ['submission /f.py', '  FAIL: imports missing on the Robotarium server: cvxpy, torch']
    view = preflight_view(report(GOOD))
    assert view.exit_code == 0 and view.data['passed'] and view.data['declare_duration_s'] == 100
    run = json.loads(json.dumps(view.data['runs'][0]))
    assert run['backend'] == 'bundled' and run['ok'] and run['counted'] == run['recounted']
    assert run['duration_s'] == pytest.approx(105 * 0.033) and preflight_view(report(timed_out)).exit_code == 1
    assert preflight_view(report(timed_out)).data['runs'][0]['counted'] is None


def test_the_build_view_unchecked_failed_and_declared() -> None:
    unchecked = build_view(pipeline.WrittenSubmission(SUB, Path('s.py'), None))
    assert unchecked.lines == (
        'submission for scene robotarium_curve (6 robots, with planning): s.py',
        '  check it before uploading:  vtube submission check s.py',
    )
    failed = build_view(pipeline.WrittenSubmission(SUB, Path('s.py'), report(RunReport('pypi', None, 1))))
    assert failed.exit_code == 1 and failed.lines[-1].endswith('fix what failed and build again')
    passed = build_view(pipeline.WrittenSubmission(SUB, Path('s.py'), report(GOOD)))
    assert passed.exit_code == 0 and passed.lines[-1] == '  the header records the declaration: 6 robots, 100 s'
    assert '  verdict                PASS' in passed.lines


def test_a_preview_build_says_it_is_not_for_upload_and_gives_the_command_that_builds_the_file_to_upload() -> None:
    """DECLARED rests on 2 initializer seeds: the line before the declaration says so; a full build's says nothing."""
    preview = build_view(pipeline.WrittenSubmission(SUB, Path('s.py'), report(GOOD))).lines
    assert preview[-2].startswith('  NOT FOR UPLOAD: this duration rests on 2 initializer seeds, not the 200 of')
    assert preview[-2].endswith(
        'Build the file to upload with `vtube submission build robotarium_curve --out experiment.py`.'
    )
    unplanned = Submission('x', 'robotarium_trapezoid', False, 6)
    line = build_view(pipeline.WrittenSubmission(unplanned, Path('s.py'), report(GOOD))).lines[-2]
    assert line.endswith('`vtube submission build robotarium_trapezoid --out experiment.py --no-planning`.')
    full = declare(InitializerSample((20.0,) * FULL_BUILD_INITIALIZER_SEEDS, ()), experiment_s=61.3)
    lines = build_view(pipeline.WrittenSubmission(SUB, Path('s.py'), report(GOOD, declaration=full))).lines
    assert not any('NOT FOR UPLOAD' in line for line in lines) and lines[-2] == '  verdict                PASS'


def preflight_on(stream: io.StringIO, monkeypatch, capsys, seeds: int) -> str:
    """``vtube submission check`` with the check stubbed: it tells what starts and ends ``seeds`` seeds."""

    def check(path, *, seeds, initializer_seeds, run_timeout_s, progress, seed_done, margin_seeds):
        assert margin_seeds == ()  # no margin search unless asked
        progress(f'running the file on the bundled simulator, seed 0 (at most {run_timeout_s:g} s)')
        for _ in range(initializer_seeds):
            seed_done()
        return report(GOOD)

    monkeypatch.setattr(check_module, 'check', check)
    monkeypatch.setattr(sys, 'stderr', stream)
    assert main(['submission', 'check', 'f.py', '--initializer-seeds', str(seeds)]) == 0
    assert 'verdict                PASS' in capsys.readouterr().out
    return stream.getvalue()


def test_the_preflight_draws_the_initializer_on_a_terminal_only(monkeypatch, capsys) -> None:
    drawn = preflight_on(Terminal(), monkeypatch, capsys, 4)
    assert "V2's initializer:" in drawn and '/4 [' in drawn  # a bar over the 4 seeds
    assert '  ... running the file on the bundled simulator, seed 0 (at most 900 s)' in drawn  # said before it waits
    piped = preflight_on(Pipe(), monkeypatch, capsys, 4)
    assert "V2's initializer" not in piped and 'seed 0 (at most 900 s)' in piped


def test_the_build_options_reach_the_pipeline(tmp_path, monkeypatch, capsys) -> None:
    calls = []

    def build_submission(scene, out, progress, seed_done, **options):
        progress('running the file on the bundled simulator, seed 10')  # the check's stages are told on stderr
        seed_done()
        calls.append((scene, out, options))
        return pipeline.WrittenSubmission(SUB, out, None)

    monkeypatch.setattr(pipeline, 'build_submission', build_submission)
    out = tmp_path / 's.py'
    argv = ['submission', 'build', 'robotarium_curve', '--out', str(out), '--seeds', '10-11']
    assert main([*argv, '--testbed-models', 'ideal, fitted', '--margin-seeds', '20-29']) == 0
    assert '  ... running the file on the bundled simulator, seed 10' in capsys.readouterr().err
    assert calls[-1] == (
        'robotarium_curve',
        out,
        {'planning': True, 'plan_file': None, 'declare': True, 'seeds': (10, 11), 'initializer_seeds': 200}
        | {'testbed_models': ('ideal', 'fitted'), 'margin_seeds': tuple(range(20, 30))},
    )
    assert main(['submission', 'build', 'x', '--out', str(out), '--no-planning', '--no-declare', '--plan', 'p']) == 0
    assert calls[-1][2]['seeds'] == (0, 1, 2)
    assert calls[-1][2] | {'seeds': 0} == {
        'planning': False,
        'plan_file': Path('p'),
        'declare': False,
        'seeds': 0,
        'initializer_seeds': 200,
        'testbed_models': None,
        'margin_seeds': (),
    }
    assert 'check it before uploading' in capsys.readouterr().out


def test_an_undeclared_build_asks_for_the_declaration(tmp_path, capsys) -> None:
    out = tmp_path / 'experiment.py'
    assert main(['submission', 'build', 'robotarium_trapezoid', '--out', str(out), '--no-declare']) == 0
    assert 'Declare on the web form: the robot count above' in out.read_text() and UNDECLARED in out.read_text()
    assert f'vtube submission check {out}' in capsys.readouterr().out


def test_submission_build_refuses_a_scene_that_does_not_fit(tmp_path, capsys) -> None:
    assert main(['submission', 'build', 'C', '--out', str(tmp_path / 'x.py')]) == 2
    assert 'does not fit the Robotarium' in capsys.readouterr().err
    assert main(['submission', 'check', str(tmp_path / 'missing.py')]) == 2


def test_a_plan_file_is_flown_as_given_and_refused_elsewhere(tmp_path, capsys) -> None:
    assert main(['plan', 'robotarium_trapezoid', '--out', str(tmp_path)]) == 0
    plan_file = tmp_path / 'plan_robotarium_trapezoid.npz'
    # a copy of the scene file is the same scene: its plan is accepted, and embedded as it is (not re-planned)
    copy = tmp_path / 'copy.toml'
    copy.write_text((ROOT / 'robotarium_exp' / 'scenes' / 'robotarium_trapezoid.toml').read_text(), encoding='utf-8')
    out = tmp_path / 'sub.py'
    build = ['submission', 'build', str(copy), '--plan', str(plan_file), '--out', str(out), '--no-declare']
    assert main(build) == 0
    namespace: dict = {}
    exec(compile(out.read_text(), 'submission', 'exec'), namespace)  # noqa: S102 -- the file just built
    slowness = np.asarray(namespace['DATA']['plan']['slowness_spm'])
    np.testing.assert_allclose(
        slowness, 1.0 / Plan.load(plan_file, load_scene(copy).tube).speed_mps, rtol=6e-6
    )  # six digits
    capsys.readouterr()
    # another tube, another swarm: refused with the reason, exit 2, nothing written
    assert main(['simulate', 'robotarium_curve', '--plan', str(plan_file), '--out', str(tmp_path / 's')]) == 2
    err = capsys.readouterr().err
    assert "(made for scene 'robotarium_trapezoid') does not fit this tube" in err
    assert 'a different tube' in err and not (tmp_path / 's').exists()
    assert main(['simulate', 'robotarium_trapezoid', '--n', '5', '--plan', str(plan_file), '--out', str(tmp_path)]) == 2
    assert 'other swarm parameters (n_robots)' in capsys.readouterr().err
    assert main(['robotarium', 'run', 'robotarium_curve', '--plan', str(plan_file), '--out', str(tmp_path)]) == 2
    analyze = ['analyze', str(tmp_path), '--scene', 'robotarium_curve', '--plan', str(plan_file)]
    assert main([*analyze, '--out', str(tmp_path / 'a')]) == 2


def test_the_delay_margin_margins_and_stress_runs_in_lines_and_json() -> None:
    from submission.delay_margin import DelayMargin, Rung
    from submission.robustness import Margins

    margin = DelayMargin((Rung(1.0, 10, 0, 0.185), Rung(1.5, 10, 2, 0.013)), 10)
    stress = RunReport('bundled', 0, 0, record=record(100), completed=True, model='fitted:2')
    margins = (Margins('fitted:2', 1, 1, 0.127, 0, 30.0, 40.0),)
    done = report(GOOD, stress_runs=(stress,), margins=margins, delay_margin=margin, margin_runs=(GOOD, stress))
    lines = check_lines(done)
    at = lines.index(f'  delay margin           {margin.summary()}')
    assert lines[at + 1 : at + 3] == [f'                           {rung.line()}' for rung in margin.rungs]
    assert 'Delay margin: 1x the fitted delay and lag' in lines[at] and 'at most 26 % of runs may fail' in lines[at + 1]
    assert any('closest centres 0.127 m (a 17 mm gap between bodies)' in line for line in lines)
    data = json.loads(json.dumps(preflight_view(done).data))
    assert data['delay_margin']['multiple'] == 1.0 and len(data['delay_margin']['rungs']) == 2
    assert [r['model'] for r in data['margin_runs']] == ['ideal', 'fitted:2'] and data['stress_runs'][0]['ok']
    assert data['margins'][0]['closest_centres_m'] == 0.127
    assert data['margins'][0]['gap_between_bodies_m'] == pytest.approx(0.017)
    assert data['runs'][0]['gap_between_bodies_m'] == pytest.approx(0.39)
    plain = preflight_view(report(GOOD)).data
    assert plain['delay_margin'] is None and plain['margin_runs'] == [] and plain['stress_runs'] == []
