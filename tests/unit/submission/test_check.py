"""The preflight's decisions, on records and runs constructed here (the runs of real files are in
``tests/integration/test_preflight.py``): imports, flight data, each run's verdict, the declaration, the order of
the runs."""

from __future__ import annotations

import ast
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import submission.check as check_module
from robotarium_exp.initializer import InitializerSample
from submission.builder import build, write
from submission.check import (
    CheckReport,
    RunReport,
    check,
    file_flight_data,
    imported_modules,
    server_libraries,
    static_check,
)
from submission.declaration import Declaration, declare
from submission.errors import CheckError
from submission.recording import SimulatorRecord
from submission.robustness import CHECKED_MODELS

ROOT = Path(__file__).resolve().parents[3]
COMMITTED = sorted(path.stem.removeprefix('vtube_') for path in (ROOT / 'submissions').glob('vtube_*.py'))
"""The scenes whose submissions are committed in ``submissions/``."""
FAKE_STEPS = 300
"""Steps of a faked run's record: its measures cost time per step, and nothing asserted depends on how many."""


def record(steps: int = 10, *, errors: dict | None = None, gap_m: float = 0.5, **change) -> SimulatorRecord:
    """Two robots ``gap_m`` apart driving along x, recorded for ``steps`` steps after 5 of initialization."""
    x = np.linspace(0.0, 0.5, steps)
    poses = np.zeros((steps, 3, 2))
    poses[:, 0, :] = x[:, None]
    poses[:, 1, 1] = gap_m
    values = {
        'poses': poses,
        'commands': np.zeros((steps, 2, 2)),
        'dt_s': 0.033,
        'errors': errors or {},
        'iterations': steps + 5,
        'initialization_steps': 5,
        'robotariums': 1,
        'end_of_script': True,
    }
    return SimulatorRecord(**(values | change))


def test_a_clean_completed_run_is_ok_and_its_durations_are_the_simulators_counts() -> None:
    run = RunReport('bundled', 3, 0, record=record(10), completed=True)
    assert run.ok and run.problems == [] and run.label == 'bundled seed 3'
    assert run.duration_s == pytest.approx(15 * 0.033) and run.experiment_s == pytest.approx(10 * 0.033)
    assert run.min_center_distance_m == pytest.approx(0.5) and run.counted.clean and run.recounted.clean
    assert RunReport('pypi', None, 0).label == 'pypi'


@pytest.mark.parametrize(
    ('run', 'problem'),
    [
        (RunReport('bundled', 0, -1, timed_out_s=3.0), 'did not finish in 3 s (raise --run-timeout if it should)'),
        (RunReport('bundled', 0, 1, 'Traceback\nValueError: x\n'), 'left no record of the simulator (exit 1)'),
        (RunReport('bundled', 0, 0, record=record(robotariums=2), completed=True), 'made 2 Robotarium objects'),
        (RunReport('bundled', 0, 3, 'boom\nKeyError: y', record=record(), completed=True), "crashed (exit 3): ['Key"),
        (RunReport('bundled', 0, 0, record=record(end_of_script=False), completed=True), 'never called debug()'),
        (
            RunReport('pypi', None, 0, record=record(errors={'boundary': 4, 'text': 'x'}), completed=True),
            'the testbed would not run it (0 pair-steps of robots too close, 4 robot-steps outside the arena)',
        ),
        (
            RunReport('bundled', 0, 0, record=record(gap_m=0.05), completed=True),
            "the verifier's rules on the simulator's recorded poses and commands count 10 pair-steps too close",
        ),
        (RunReport('bundled', 0, 0, record=record(), completed=False), 'not every robot parked beyond the exit'),
    ],
)
def test_each_reason_a_run_fails(run: RunReport, problem: str) -> None:
    assert not run.ok and any(problem in found for found in run.problems), run.problems


def test_the_report_passes_only_with_runs_all_ok_and_no_problem() -> None:
    good = RunReport('bundled', 0, 0, record=record(), completed=True)
    bad = RunReport('pypi', None, 0, record=record(), completed=False)
    assert CheckReport('f.py', runs=(good,)).passed and not CheckReport('f.py').passed  # no runs: not passed
    failed = CheckReport('f.py', runs=(good, bad), declaration_problem='declare more.')
    assert not failed.passed and failed.problems == [
        'pypi: not every robot parked beyond the exit by the last step',
        'declare more.',
    ]
    imports = CheckReport('f.py', disallowed_imports=('cvxpy',))
    assert imports.problems == ['imports missing on the Robotarium server: cvxpy'] and not imports.passed
    assert CheckReport('f.py', runs=(good,)).experiment_s == pytest.approx(10 * 0.033)
    assert CheckReport('f.py').experiment_s is None and CheckReport('f.py').declare_duration_s is None


def test_server_libraries_are_import_names() -> None:
    names = server_libraries()
    assert {'numpy', 'scipy', 'matplotlib', 'cvxopt', 'rps'} <= names and 'cvxpy' not in names
    assert all('-' not in name and name == name.lower() for name in names)


@pytest.mark.parametrize('scene', COMMITTED)
def test_submission_imports_only_what_the_server_has_and_parses_as_python_310(scene: str) -> None:
    source = (ROOT / 'submissions' / f'vtube_{scene}.py').read_text(encoding='utf-8')
    ast.parse(source, feature_version=(3, 10))
    assert static_check(source) == []
    standard = {
        '__future__',
        'collections',
        'dataclasses',
        'functools',
        'itertools',
        'json',
        'math',
        'os',
        'time',
        'typing',
    }
    assert imported_modules(source) <= standard | {'numpy', 'scipy', 'rps'}
    assert static_check(source + '\nimport cvxpy\nfrom rosbags.highlevel import AnyReader\n') == ['cvxpy', 'rosbags']
    assert imported_modules('from . import x\nimport a.b as c\ndef f():\n    import d\n') == {'a', 'd'}


def test_the_flight_data_is_read_without_running_the_file() -> None:
    source = (ROOT / 'submissions' / 'vtube_robotarium_curve.py').read_text(encoding='utf-8')
    data = file_flight_data(source)
    assert data.scene == 'robotarium_curve' and data.n_robots == 6 and data.planned
    with pytest.raises(CheckError, match='has no DATA with flight data'):
        file_flight_data('x = 1\n')
    with pytest.raises(CheckError, match="the file's DATA is not vtube flight data"):
        file_flight_data('DATA = {"tube": 1}\n')


def test_files_that_cannot_be_checked_are_refused(tmp_path) -> None:
    with pytest.raises(CheckError, match='is a folder; give the submission .py file'):
        check(tmp_path)
    with pytest.raises(CheckError, match='does not exist'):
        check(tmp_path / 'none.py')
    (tmp_path / 'latin.py').write_bytes(b'# caf\xe9\n')
    with pytest.raises(CheckError, match='not UTF-8 text'):
        check(tmp_path / 'latin.py')
    (tmp_path / 'broken.py').write_text('def (:\n')
    with pytest.raises(CheckError, match='is not valid Python 3.10'):
        check(tmp_path / 'broken.py')
    (tmp_path / 'ok.py').write_text('x = 1\n')
    with pytest.raises(CheckError, match='check with seeds >= 1'):
        check(tmp_path / 'ok.py', seeds=0)
    (tmp_path / 'cvx.py').write_text('import cvxpy\n')
    assert check(tmp_path / 'cvx.py').disallowed_imports == ('cvxpy',)  # refused before any run


@pytest.fixture
def fake_runs(monkeypatch):
    """``run_file`` and the initializer stubbed: each run a clean record of `FAKE_STEPS` steps; the calls in order."""
    calls: list[object] = []

    def run_file(path, backend, seed, data, timeout_s, model='ideal', *, reuse=True, salt=None):
        calls.append((backend, seed, timeout_s) + ((model,) if model != 'ideal' else ()))
        return RunReport(backend, seed, 0, record=record(FAKE_STEPS), completed=True, model=model)

    def initializer(ic, seeds, seed_done=None):
        for _ in seeds:
            calls.append('seed done')
            (seed_done or (lambda: None))()
        return InitializerSample(tuple(20.0 + s for s in seeds), ())

    monkeypatch.setattr(check_module, 'run_file', run_file)
    monkeypatch.setattr(check_module, 'cached_initializer_durations', initializer)
    find_spec = check_module.importlib.util.find_spec
    installed = lambda name, *args: object() if name == 'rps' else find_spec(name, *args)
    monkeypatch.setattr(check_module.importlib.util, 'find_spec', installed)  # the PyPI simulator is installed
    return calls


def test_check_runs_each_seed_then_the_pypi_simulator_then_the_initializer(tmp_path, fake_runs) -> None:
    path = write(build('robotarium_trapezoid', None), tmp_path / 'sub.py')
    told: list[str] = []
    report = check(path, seeds=2, initializer_seeds=3, run_timeout_s=7.0, progress=told.append, seed_done=lambda: None)
    models = [('bundled', seed, 7.0, model) for model in ('fitted', 'fitted:2') for seed in (0, 1)]
    ideal = [('bundled', 0, 7.0), ('bundled', 1, 7.0)]
    # two batches over the cores: the ideal runs and the PyPI run, then the other models; then the initializer
    assert sorted(map(str, fake_runs[:3])) == sorted(map(str, [*ideal, ('pypi', None, 7.0)]))
    assert sorted(map(str, fake_runs[3:7])) == sorted(map(str, models)) and fake_runs[7:] == ['seed done'] * 3
    assert [run.label for run in report.runs] == [
        'bundled seed 0',
        'bundled seed 1',
        'bundled seed 0 fitted',
        'bundled seed 1 fitted',
        'pypi',
    ]
    assert [run.label for run in report.stress_runs] == ['bundled seed 0 fitted:2', 'bundled seed 1 fitted:2']
    assert report.passed and [(m.model, m.runs, m.clean) for m in report.margins] == [
        ('ideal', 2, 2),
        ('fitted', 2, 2),
        ('fitted:2', 2, 2),
    ]
    bundled = 'running the file on the bundled simulator, seed {}{} (at most 7 s)'
    assert told == [
        *[bundled.format(s, '') for s in (0, 1)],
        'running the file on the PyPI simulator (at most 7 s)',
        *[bundled.format(s, ', ' + m) for m in CHECKED_MODELS[1:] for s in (0, 1)],
        "V2's initializer alone for the file's initial conditions, 3 seeds",
    ]
    assert report.robots == 2 and report.header_declaration is None  # the simulator's count, not the file's
    expected = declare(InitializerSample((20.0, 21.0, 22.0), ()), experiment_s=FAKE_STEPS * 0.033)
    assert report.declaration == replace(expected, margins=report.margins)
    assert report.declare_duration_s == expected.duration_s
    fake_runs.clear()
    report = check(path, seeds=(5, 3), initializer_seeds=1, run_timeout_s=7.0, testbed_models=('ideal',))
    assert sorted(map(str, fake_runs[:2])) == sorted(map(str, [('bundled', 5, 7.0), ('bundled', 3, 7.0)]))
    assert [run.seed for run in report.runs] == [5, 3, None]  # the seeds given, in their order, then PyPI's


def test_the_header_records_the_declaration_and_the_check_reads_it_back(tmp_path, fake_runs) -> None:
    declaration = declare(InitializerSample((20.0, 35.5, 80.25), ()), experiment_s=61.3)
    source = build('robotarium_trapezoid', None, declaration=declaration).source
    header = source[: source.index('from __future__')]
    assert 'Declare on the web form: 6 robots and 150 s, derived by `vtube submission check`' in header
    assert 'from initializer 99.5% over 3 seeds 80.2 s + experiment 61.3 s; overruns 0.0%, stuck 0.0%.' in header
    recorded = Declaration.from_header(source)
    assert recorded is not None and recorded.duration_s == 150 and recorded.runs == 3
    again = check(
        write(build('robotarium_trapezoid', None, declaration=recorded), tmp_path / 'a.py'), initializer_seeds=3
    )
    assert again.passed, again.problems
    short = declare(InitializerSample((1.0,), ()), experiment_s=1.0)  # 10 s: shorter than any real run
    path = write(build('robotarium_trapezoid', None, declaration=short), tmp_path / 'short.py')
    report = check(path, seeds=1, initializer_seeds=2)
    assert not report.passed and report.header_declaration == short
    assert report.declaration is not None and report.declaration.duration_s > 10
    assert report.declaration_problem.startswith(
        f'the header records 10 s, shorter than the {report.declaration.duration_s} s derived now; declare'
    )


def test_the_declaration_is_derived_and_every_run_must_fit_its_margin() -> None:
    sample = InitializerSample((1.0,), ())
    stuck = CheckReport('f.py', runs=(RunReport('bundled', 0, 0, record=record(2000), completed=True),))
    found = check_module._declared(stuck, InitializerSample((), (0,)))
    assert 'did not finish' in found.declaration_problem and found.declaration is None
    assert check_module._declared(CheckReport('f.py'), sample) == CheckReport('f.py')  # no experiment: nothing
    # 100 steps of experiment after 20000 of initialization: 663 s on the testbed's clock
    late = RunReport(
        'bundled', 1, 0, record=record(100, iterations=20_100, initialization_steps=20_000), completed=True
    )
    header = Declaration(400, 1.0, 1.0, 1, 0.0, 0.0)  # at least the 10 s derived; the verifier allows 600 s
    report = check_module._declared(CheckReport('f.py', runs=(late,), header_declaration=header), sample)
    assert report.declaration == declare(sample, 100 * 0.033) and report.declaration.duration_s == 10
    assert report.declaration_problem == (
        "bundled seed 1 took 663.3 s by the simulator's count, beyond the 600 s the verifier allows for a "
        'declaration of 400 s; declare more.'
    )
    fits = Declaration(450, 1.0, 1.0, 1, 0.0, 0.0)  # 675 s allowed
    assert check_module._declared(CheckReport('f.py', runs=(late,), header_declaration=fits), sample).passed


def test_completion_is_every_robot_past_the_exit_of_the_files_tube() -> None:
    source = (ROOT / 'submissions' / 'vtube_robotarium_curve.py').read_text(encoding='utf-8')
    data = file_flight_data(source)
    xy = np.asarray(data.tube.xy_m)  # (2, K): the polyline's samples
    heading = (xy[:, -1] - xy[:, -2]) / np.linalg.norm(xy[:, -1] - xy[:, -2])
    past = np.zeros((1, 3, 6))
    past[0, :2] = (xy[:, -1] + 0.3 * heading)[:, None]
    start = np.zeros((1, 3, 6))
    start[0, :2] = xy[:, :1]
    rec = record(1)
    assert check_module._completed(SimulatorRecord(past, *_rest(rec)), data)
    assert not check_module._completed(SimulatorRecord(start, *_rest(rec)), data)
    assert not check_module._completed(None, data) and not check_module._completed(rec, data)  # 2 robots, not 6


def _rest(rec: SimulatorRecord) -> tuple:
    return (np.zeros((1, 2, 6)), rec.dt_s, rec.errors, rec.iterations, rec.initialization_steps, 1, True)


def _stub_runs(monkeypatch, bad, bad_gap_m: float) -> list[tuple[int | None, str]]:
    """The check's runs stubbed: a run that is ``bad(seed, model)`` brings two robots ``bad_gap_m`` apart, every
    other 0.5 m; the initializer sample stubbed too. The (seed, model) of the bundled runs flown, as they fly."""
    flown: list[tuple[int | None, str]] = []

    def run_file(path, backend, seed, data, timeout_s, model='ideal', *, reuse=True, salt=None):
        if backend == 'bundled':
            flown.append((seed, model))
        failed = bad(seed, model)
        errors = {'robots_too_close': 4} if failed else None
        return RunReport(backend, seed, 0, record=record(FAKE_STEPS, errors=errors, gap_m=bad_gap_m if failed else 0.5),
                         completed=True, model=model)  # fmt: skip

    monkeypatch.setattr(check_module, 'run_file', run_file)
    monkeypatch.setattr(
        check_module, 'cached_initializer_durations', lambda ic, seeds, seed_done=None: InitializerSample((20.0,), ())
    )
    return flown


def test_a_stress_model_reports_margins_and_a_verdict_model_decides(tmp_path, monkeypatch) -> None:
    """A run that fails under fitted:2 is a stress result (the file passes, its margins say so); under fitted it
    fails the file; when the ideal runs fail already, no other model is flown."""
    path = write(build('robotarium_trapezoid', None), tmp_path / 'sub.py')
    failing: set[str] = set()
    flown = _stub_runs(monkeypatch, lambda seed, model: model in failing, 0.1)
    for case, passes, models in [
        ({'fitted:2'}, True, list(CHECKED_MODELS)),
        ({'fitted'}, False, list(CHECKED_MODELS)),
        ({'ideal'}, False, ['ideal']),
    ]:
        failing.clear()
        failing.update(case)
        flown.clear()
        report = check(path, seeds=1, initializer_seeds=1)
        assert report.passed == passes and sorted(m for _, m in flown) == sorted(models), failing
        margins = {m.model: m for m in report.margins}
        assert sorted(margins) == sorted(models)
        for model, margin in margins.items():
            assert margin.clean == (model not in failing)
            assert margin.min_distance_m == pytest.approx(0.1 if model in failing else 0.5)
    assert not any('fitted:2' in problem for problem in report.problems)


def test_the_margins_are_measured_on_the_tube_and_read_back_from_the_header(tmp_path) -> None:
    """On the shipped trapezoid (straight along x, l = x + 1.45): the margins' passing time and body-on-wall steps
    recomputed by hand, and the header's lines read back as the same margins."""
    from robotarium_exp.experiment import ExperimentConfig, flight_data
    from robotarium_exp.scene import load_scene
    from robotarium_exp.spec import ROBOTARIUM
    from submission.robustness import Margins, from_header, margins

    scene = load_scene('robotarium_trapezoid')
    data = flight_data(scene, None, ExperimentConfig(planning=False))
    steps = 300
    poses = np.zeros((steps, 3, 2))
    poses[:, 0, :] = -1.40 + 0.01 * np.arange(steps)[:, None]  # 1 cm a step along the axis, from l = 0.05 m
    poses[:, 1, 0], poses[:, 1, 1] = 0.2, -0.2
    run = SimulatorRecord(poses, np.zeros((steps, 2, 2)), 0.033, {}, steps, 0, 1, True)
    found = margins('fitted', [(True, run, steps * 0.033), (False, None, None)], data)
    l_m = poses[:, 0, 0] + 1.45
    inside = l_m <= scene.tube.length_m
    assert found.runs == 2 and found.clean == 1 and found.min_distance_m == pytest.approx(0.4)
    assert found.passing_time_s == pytest.approx(np.argmin(inside) * 0.033, abs=0.034)  # the last robot out
    over = 0.2 + 0.5 * ROBOTARIUM.robot_diameter_m > scene.tube.half_width(np.minimum(l_m, scene.tube.length_m))
    expected = 2 * int((over & inside).sum())  # both robots, symmetric
    assert expected > 20 and abs(found.wall_steps - expected) <= 4  # the sampled tube against the exact one
    declaration = replace(declare(InitializerSample((20.0,), ()), experiment_s=30.0), margins=(found,))
    source = build('robotarium_trapezoid', None, declaration=declaration).source
    rounded = Margins('fitted', 2, 1, round(found.min_distance_m, 3), found.wall_steps,
                      round(found.passing_time_s, 1), round(found.duration_s, 1))  # fmt: skip
    assert from_header(source) == (rounded,) and Declaration.from_header(source).margins == (rounded,)


def test_the_check_searches_the_delay_margin_only_when_asked_and_the_header_records_it(tmp_path, monkeypatch) -> None:
    """Stubbed runs fail from 2.5x on: the margin is 2x over the 10 seeds; the check's own fitted and fitted:2 runs
    (seeds 0, 1) are reused, and a file whose verdict runs fail gets no search."""
    from submission.delay_margin import from_header

    path = write(build('robotarium_trapezoid', None), tmp_path / 'sub.py')
    failing: set[str] = {'fitted:2.5'}
    flown = _stub_runs(monkeypatch, lambda seed, model: model in failing and seed == 7, 0.05)
    plain = check(path, seeds=2, initializer_seeds=1)
    assert plain.delay_margin is None and plain.margin_runs == () and len(flown) == 6
    flown.clear()
    report = check(path, seeds=2, initializer_seeds=1, margin_seeds=range(10))
    margin = report.delay_margin
    assert report.passed and margin is not None and margin.multiple == 2.0 and margin.seeds == 10
    assert [(r.multiple, r.failed) for r in margin.rungs] == [(1, 0), (1.5, 0), (2, 0), (2.5, 1)]
    assert margin.rungs[-1].closest_centres_m == pytest.approx(0.05)
    assert flown.count((0, 'fitted')) == flown.count((1, 'fitted:2')) == 1  # the check's runs, not flown again
    assert len(flown) == 6 + 8 + 10 + 8 + 10 and len(report.margin_runs) == 40
    assert report.declaration is not None and report.declaration.delay_margin == margin
    stamped = build('robotarium_trapezoid', None, declaration=report.declaration).source
    assert 'Delay margin: 2x the fitted delay and lag (testbed model fitted, version' in stamped
    assert from_header(stamped) == margin and Declaration.from_header(stamped).delay_margin == margin
    failing.add('fitted')  # seed 7 is not a verdict seed: the verdict passes, the margin is none
    assert check(path, seeds=2, initializer_seeds=1, margin_seeds=range(10)).delay_margin.multiple is None
    failing.add('ideal')
    flown.clear()
    assert check(path, seeds=(7,), initializer_seeds=1, margin_seeds=range(10)).delay_margin is None
    assert {m for _, m in flown} == {'ideal'}
    with pytest.raises(CheckError, match='at least 10 seeds'):
        check(path, seeds=1, initializer_seeds=1, margin_seeds=range(4))
