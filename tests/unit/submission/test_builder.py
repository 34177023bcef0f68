"""The single-file submission: reproducible, server-safe, accepted by both simulators, fast enough."""

from __future__ import annotations

import ast
import functools
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from robotarium_exp.analysis.loaders import load_trajectory
from robotarium_exp.experiment import ExperimentConfig, flight_data, run_experiment
from robotarium_exp.flight_data import FlightData
from robotarium_exp.initializer import InitializerSample
from robotarium_exp.rps.robotarium import Robotarium
from robotarium_exp.rps_alias import seed_rps
from robotarium_exp.spec import ROBOTARIUM
from submission import runtime
from submission.builder import BUILD_STAMP, UNDECLARED, SubmissionError, build, write
from submission.check import check, imported_modules, static_check
from submission.declaration import Declaration, declare
from submission.errors import CheckError
from vtube_planning import SceneError, load_scene
from vtube_planning.onboard import PlanProfile, SampledTube, StepParams, SwarmStep
from vtube_planning.planning.plan import Plan
from vtube_planning.planning.planner import plan_convex
from vtube_planning.swarm.metrics import passage_metrics

ROOT = Path(__file__).resolve().parents[2]
SCENES = ('robotarium_trapezoid', 'robotarium_curve')


def namespace_of(source: str) -> dict:
    namespace: dict = {}
    exec(compile(source, 'submission', 'exec'), namespace)  # noqa: S102 -- our generated file: defines, runs nothing
    return namespace


def data_of(source: str) -> dict:
    return namespace_of(source)['DATA']


@functools.cache
def shipped_plan(scene: str) -> Plan:
    """The plan of a shipped scene (planned once per test session)."""
    loaded = load_scene(scene)
    return plan_convex(loaded.tube, loaded.swarm, loaded.planning, scene=loaded.name)


def planned(path: str | Path) -> str:
    """The source of a planned build of a scene file or shipped scene."""
    scene = load_scene(path)
    return build(scene, plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)).source


def variant(tmp_path: Path, scene: str, control_line: str) -> Path:
    """A copy of a shipped scene with one more line under [control], as a user would write it."""
    text = (ROOT / 'vtube_planning' / 'scenes' / f'{scene}.toml').read_text(encoding='utf-8')
    path = tmp_path / f'{scene}_variant.toml'
    key = control_line.split('=')[0].strip()
    lines = [line for line in text.splitlines() if not line.startswith(f'{key} =')]  # the variant's value wins
    text = '\n'.join(lines).replace('[control]', f'[control]\n{control_line}')
    path.write_text(text, encoding='utf-8')
    return path


@pytest.mark.parametrize('control_line', ['law = "practical"', 'feedforward = false'])
def test_the_inlined_step_is_the_library_step(tmp_path, control_line: str) -> None:
    """The submission's own SwarmStep (its inlined source, its rounded data) commands what the package's does."""
    ns = namespace_of(planned(variant(tmp_path, 'robotarium_curve', control_line)))
    data = ns['DATA']
    assert ns['SwarmStep'] is not SwarmStep  # really the file's copy

    def stepper(module_classes: tuple) -> object:
        tube_cls, params_cls, plan_cls, step_cls = module_classes
        plan = plan_cls(**{k: np.asarray(v) for k, v in data['plan'].items()})
        return step_cls(
            tube_cls(**data['tube']),
            params_cls(**data['step']),
            6,
            plan=plan,
            constant_speed_mps=data['constant_speed_mps'],
            parking_slots=np.asarray(data['parking_slots']),
        )

    inlined = stepper((ns['SampledTube'], ns['StepParams'], ns['PlanProfile'], ns['SwarmStep']))
    library = stepper((SampledTube, StepParams, PlanProfile, SwarmStep))
    rng = np.random.default_rng(3)
    tube = load_scene('robotarium_curve').tube
    for _ in range(40):  # random swarms along the tube, some past the exit (parking), radii evolving by (a3)
        l = rng.uniform(-0.2, tube.length_m + 0.3) + rng.uniform(-0.15, 0.15, 6)  # compact: denser than planned
        points = (tube.center_at(l) + rng.uniform(-0.2, 0.2, 6)[:, None] * tube.normal(l)).T
        a, b = inlined(points, 0.033), library(points, 0.033)
        np.testing.assert_allclose(a.velocity, b.velocity, rtol=0, atol=1e-12)
        np.testing.assert_allclose(a.r_a_m, b.r_a_m, rtol=0, atol=1e-12)
        assert a.density_per_m2 == pytest.approx(b.density_per_m2, abs=1e-12) and a.done == b.done
    assert np.any(library.r_a > data['step']['r_a_m'])  # the radii did move


@pytest.mark.slow
def test_the_submission_flies_the_bundled_experiment(tmp_path) -> None:
    """Same scene variant, same V2 initialization draws: the experiment and the built file fly the same poses."""
    path = variant(tmp_path, 'robotarium_trapezoid', 'law = "practical"')
    scene = load_scene(path)
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    seed_rps(0)
    experiment = run_experiment(Robotarium, scene, plan, ExperimentConfig())
    work = tmp_path / 'testbed'
    work.mkdir()
    file = write(build(scene, plan), work / 'submission.py')
    env = dict(os.environ, VTUBE_HEADLESS='1')
    done = subprocess.run(
        [sys.executable, '-m', 'robotarium_exp.rps_alias', '--seed', '0', str(file)],
        cwd=work,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    positions, t = np.load(work / 'vtube_positions_m.npy'), np.load(work / 'vtube_t_s.npy')
    robots = [scene.tube.project(p) for p in positions]
    returned = passage_metrics(
        t,
        positions,
        np.array([p.l_m for p in robots]),
        np.array([p.clearance_m for p in robots]),
        scene.tube.length_m,
        collision_distance_m=2 * scene.swarm.r_p_m,
        body_radius_m=0.5 * ROBOTARIUM.robot_diameter_m,
    )
    mine = experiment.metrics
    assert returned.passing_time_s == pytest.approx(mine.passing_time_s, rel=0.01)
    assert returned.min_distance_m == pytest.approx(mine.min_distance_m, abs=0.005)
    assert returned.tube_violation_steps == pytest.approx(mine.tube_violation_steps, rel=0.05)
    assert mine.tube_violation_steps > 0  # the practical law leaves the tube here: the variant really flew
    np.testing.assert_allclose(positions, experiment.arrays['positions_m'], atol=1e-9)  # in fact, the same trajectory


@pytest.mark.parametrize('scene', SCENES)
def test_committed_submission_equals_a_fresh_build(scene: str) -> None:
    """Byte for byte, given the declaration its header records (derived by the check over 200 seeds)."""
    committed = (ROOT / 'submissions' / f'vtube_{scene}.py').read_text(encoding='utf-8')
    recorded = Declaration.from_header(committed)
    assert recorded is not None and recorded.runs == 200 and recorded.stuck_share == 0.0
    fresh = build(scene, shipped_plan(scene), declaration=recorded).source
    assert _unstamped(fresh) == _unstamped(committed), (
        f'rebuild with: vtube submission build {scene} --out submissions/vtube_{scene}.py'
    )
    assert fresh.count(BUILD_STAMP) == 1 and fresh != _unstamped(fresh)  # the stamp is there, and only there


def _unstamped(source: str) -> str:
    """A built file without its build stamp (when and by which command: the one line that differs by build)."""
    return '\n'.join(line for line in source.splitlines() if not line.startswith(BUILD_STAMP))


@pytest.mark.parametrize('scene', SCENES)
def test_submission_imports_only_what_the_server_has_and_parses_as_python_310(scene: str) -> None:
    source = (ROOT / 'submissions' / f'vtube_{scene}.py').read_text(encoding='utf-8')
    ast.parse(source, feature_version=(3, 10))
    assert static_check(source) == []
    standard = {'__future__', 'collections', 'dataclasses', 'functools', 'json', 'math', 'os', 'time', 'typing'}
    assert imported_modules(source) <= standard | {'numpy', 'scipy', 'rps'}
    assert static_check(source + '\nimport cvxpy\nfrom rosbags.highlevel import AnyReader\n') == ['cvxpy', 'rosbags']


@pytest.mark.parametrize('scene', SCENES)
@pytest.mark.slow
def test_committed_submission_passes_the_preflight_on_both_simulators(scene: str) -> None:
    pytest.importorskip('rps.robotarium')  # the PyPI simulator (test extra)
    report = check(ROOT / 'submissions' / f'vtube_{scene}.py', seeds=2, initializer_seeds=4)
    assert [run.backend for run in report.runs] == ['bundled', 'bundled', 'pypi']
    for run in report.runs:
        assert run.ok, (run.label, run.problems, run.stderr_tail)
        assert run.min_center_distance_m > 0.135
    assert report.passed and report.robots == 6
    assert report.header_declaration is not None  # 200 seeds: at least what 4 seeds derive
    assert report.header_declaration.duration_s >= report.declaration.duration_s
    declared = report.declaration
    assert declared is not None and report.initializer is not None and report.initializer.runs == 4
    assert declared.duration_s >= max(report.initializer.durations_s) + declared.experiment_s - 10  # 4 seeds: max
    for run in report.runs:  # every checked run fits the verifier's 1.5 x the declaration
        assert run.duration_s <= 1.5 * declared.duration_s


def test_saved_arrays_load_without_pickle(tmp_path, monkeypatch) -> None:
    import importlib
    import sys

    from robotarium_exp.rps_alias import CLASSIC_MODULES
    from robotarium_exp.rps_classic import robotarium as classic

    for suffix in CLASSIC_MODULES:  # `import rps...` in the runtime resolves to the classic tree, for this test only
        monkeypatch.setitem(sys.modules, 'rps' + suffix, importlib.import_module('robotarium_exp.rps_classic' + suffix))

    class Module:  # robots placed at the initial conditions
        Robotarium = classic.Robotarium

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv('VTUBE_HEADLESS', '1')
    data = FlightData.from_plain(data_of(build('robotarium_curve', shipped_plan('robotarium_curve')).source))
    summary = runtime.run(data, Module, max_steps=150)
    positions = np.load(tmp_path / 'vtube_positions_m.npy', allow_pickle=False)
    assert positions.shape == (summary['steps'], 2, 6)
    for name in ('t_s', 'headings_rad', 'dxu', 'r_a_m', 'points_l_m', 'density_per_m2', 'barrier_correction_mps'):
        assert np.load(tmp_path / f'vtube_{name}.npy', allow_pickle=False).shape[0] == summary['steps']
    meta = json.loads((tmp_path / 'vtube_meta.json').read_text())
    assert meta['format'] == 'vtube-trajectory' and meta['version'] == 2 and meta['finished']
    assert (
        meta['scene'] == 'robotarium_curve' and meta['tube_hash'] == load_scene('robotarium_curve').tube.fingerprint()
    )
    returned = load_trajectory([tmp_path])  # the one reader of vtube logs
    assert returned.source['tube_hash'] == meta['tube_hash'] and len(returned.robot_ids) == 6
    np.testing.assert_array_equal(returned.positions_m, positions)


def test_sampled_tube_matches_the_exact_projection() -> None:
    for scene_name in SCENES:
        scene = load_scene(scene_name)
        tube = SampledTube(**data_of(build(scene_name, None).source)['tube'])
        rng = np.random.default_rng(0)
        l = rng.uniform(0.0, scene.tube.length_m, 500)
        y = rng.uniform(-1, 1, 500) * scene.tube.half_width(l)
        points = (scene.tube.center_at(l) + y[:, None] * scene.tube.normal(l)).T
        got = tube.project(points)
        # a 1 cm polyline: a point at offset y from a bend of curvature kappa lands up to |y| kappa h / 2 away
        # along a chord of length h: 0.5 m x 1.07 / m x 0.01 m / 2 = 2.7 mm at most on these tubes
        worst = 0.5 * float(np.abs(scene.tube.curvature(np.linspace(0, scene.tube.length_m, 2000))).max()) * 0.01 / 2
        assert np.abs(got.l_m - l).max() <= worst + 2e-5  # + the data's six significant digits
        assert np.all(np.abs(got.y_m - y) <= 2e-4)
        np.testing.assert_allclose(tube.area(l), scene.tube.area(l), rtol=1e-4)  # linear between 1 cm samples
        outside = np.array([-0.3, scene.tube.length_m + 0.4])  # the straight extensions keep the end widths
        np.testing.assert_allclose(tube.area(outside), scene.tube.area(outside), rtol=1e-4)


@pytest.mark.parametrize(
    ('scene', 'error', 'match'),
    [
        ('robotarium_ellipse', SceneError, "unknown scene 'robotarium_ellipse'"),
        ('A', SubmissionError, 'does not fit the Robotarium arena'),
    ],
)
def test_bad_builder_input(scene: str, error: type, match: str) -> None:
    with pytest.raises(error, match=match):
        build(scene, None)


def test_too_many_robots(tmp_path) -> None:
    text = (ROOT / 'vtube_planning' / 'scenes' / 'robotarium_trapezoid.toml').read_text()
    path = tmp_path / 'crowd.toml'
    path.write_text(text.replace('n_robots = 6', 'n_robots = 24'))
    with pytest.raises(SubmissionError, match='has 24 robots; the Robotarium runs at most 20'):
        build(path, None)


def test_the_declared_duration_covers_a_high_quantile_of_the_initializer() -> None:
    """Synthetic samples: the 99.5 % quantile plus the experiment, rounded up to 10 s; risks as measured shares."""
    spread = InitializerSample(tuple(float(k) for k in range(1, 201)), ())
    plain = declare(spread, experiment_s=30.0)
    assert plain.quantile_s == 200.0 and plain.duration_s == 230 and plain.overrun_share == 0.0  # 200: the longest
    heavy = declare(InitializerSample((10.0,) * 190 + (500.0,) * 10, ()), experiment_s=30.0)
    assert heavy.duration_s == 530  # a tail over 0.5 % is covered, not averaged away
    tail = declare(InitializerSample((10.0,) * 399 + (2000.0,), ()), experiment_s=30.0)
    assert tail.duration_s == 40 and tail.overrun_share == pytest.approx(0.0025)  # beyond 1.5 x 40 s: reported
    stuck = declare(InitializerSample((10.0,) * 399, (5,)), experiment_s=30.0)
    assert stuck.stuck_share == pytest.approx(0.0025) and stuck.overrun_share == pytest.approx(0.0025)
    with pytest.raises(CheckError, match=r'3 of 200 initializations did not finish .* change the initial'):
        declare(InitializerSample((10.0,) * 197, (1, 2, 3)), experiment_s=30.0)


@pytest.mark.slow
def test_the_header_records_the_declaration_and_the_check_reads_it_back(tmp_path) -> None:
    declaration = declare(InitializerSample((20.0, 35.5, 80.25), ()), experiment_s=61.3)
    plan = shipped_plan('robotarium_trapezoid')
    source = build('robotarium_trapezoid', plan, declaration=declaration).source
    header = source[: source.index('from __future__')]
    assert 'Declare on the web form: 6 robots and 150 s, derived by `vtube submission check`' in header
    assert 'from initializer 99.5% over 3 seeds 80.2 s + experiment 61.3 s; overruns 0.0%, stuck 0.0%.' in header
    recorded = Declaration.from_header(source)
    assert recorded is not None and recorded.duration_s == 150 and recorded.runs == 3
    again = build('robotarium_trapezoid', plan, declaration=recorded).source
    assert _unstamped(again) == _unstamped(source)  # the text round-trips (the build stamp's second may differ)
    assert Declaration.from_header(build('robotarium_trapezoid', plan).source) is None
    short = declare(InitializerSample((1.0,), ()), experiment_s=1.0)  # 10 s: shorter than any real run
    path = write(build('robotarium_trapezoid', plan, declaration=short), tmp_path / 'short.py')
    report = check(path, seeds=1, initializer_seeds=2)
    assert not report.passed
    assert report.declaration is not None and report.declaration.duration_s > 10
    assert report.declaration_problem.startswith(
        f'the header records 10 s, shorter than the {report.declaration.duration_s} s derived now; declare'
    )


def test_the_builder_refuses_initial_conditions_that_can_stall_the_initializer(monkeypatch) -> None:
    """The old order (robot 1 in the middle of the front row) left trapezoid seed 38 stuck for good in V2."""
    from robotarium_exp import experiment

    monkeypatch.setattr(experiment, 'order_for_v2_initializer', lambda ic: list(range(ic.shape[1])))
    with pytest.raises(SubmissionError, match=r"'robotarium_trapezoid': robots 0 and 1 start at slots with 2 and 3 "):
        build('robotarium_trapezoid', None)


def test_an_unplanned_file_carries_no_plan_and_its_header_describes_none() -> None:
    unplanned = build('robotarium_curve', None)
    header = unplanned.source[: unplanned.source.index('from __future__')]
    assert data_of(unplanned.source)['plan'] is None and not unplanned.planned
    assert 'No plan: constant forward speed 0.08 m/s and constant avoidance radius 0.3 m.' in header
    assert 'Plan:' not in header and 'certificate' not in header and '--no-planning' in header
    planned_header = planned('robotarium_curve')
    assert 'Plan: convex slowness method, ' in planned_header[: planned_header.index('from __future__')]


def test_the_header_lists_the_imports_read_from_the_file() -> None:
    source = build('robotarium_trapezoid', None).source
    header = ' '.join(source[: source.index('from __future__')].split())
    found = imported_modules(source) - {'__future__'}
    assert 'scipy' in found and 'numpy' in found and 'rps' in found
    packages = sorted(found & {'numpy', 'scipy', 'rps'})
    listed = ', '.join("the testbed's rps" if m == 'rps' else m for m in packages)
    standard = ', '.join(sorted(found - {'numpy', 'scipy', 'rps'}))
    assert f'It imports {listed} and, from the standard library, {standard}.' in header


def test_the_declaration_is_stamped_into_the_built_file() -> None:
    """One build: the declaration replaces the header's request for one, and nothing else changes."""
    submission = build('robotarium_trapezoid', None)
    declaration = declare(InitializerSample((20.0, 35.5), ()), experiment_s=61.3)
    declared = submission.declared(declaration)
    assert UNDECLARED in submission.source and UNDECLARED not in declared.source
    assert Declaration.from_header(declared.source) == declaration
    before, after = submission.source.split(UNDECLARED)
    assert declared.source.startswith(before) and declared.source.endswith(after)
    with pytest.raises(SubmissionError, match='already records a declaration'):
        declared.declared(declaration)


STEPS_OUTSIDE = 150


def lying_file(tmp_path: Path) -> Path:
    """Two robots driven backwards out of the arena by a file that prints a clean vtube summary."""
    text = (ROOT / 'vtube_planning' / 'scenes' / 'robotarium_curve.toml').read_text(encoding='utf-8')
    scene_path = tmp_path / 'pair.toml'
    scene_path.write_text(text.replace('n_robots = 6', 'n_robots = 2'), encoding='utf-8')
    data = flight_data(load_scene(scene_path), None, ExperimentConfig(planning=False))
    clean = {'vtube_summary': 1, 'robots': 2, 'completed': True, 'errors': {}, 'min_center_distance_m': 0.4}
    path = tmp_path / 'lying.py'
    path.write_text(
        '\n'.join(
            [
                'import json',
                'import numpy as np',
                'import rps.robotarium as robotarium',
                f'DATA = {data.to_plain()!r}',
                "ic = np.array(DATA['initial_conditions'])",
                'headless = {"show_figure": False, "sim_in_real_time": False}',
                'r = robotarium.Robotarium(number_of_robots=2, initial_conditions=ic, **headless)',
                f'for _ in range({STEPS_OUTSIDE}):',
                '    r.get_poses()',
                '    r.set_velocities(np.arange(2), np.array([[-0.1, -0.1], [0.0, 0.0]]))',
                '    r.step()',
                f'print(json.dumps({clean!r}))',
                "r.debug() if hasattr(r, 'debug') else r.call_at_scripts_end()",
                '',
            ]
        ),
        encoding='utf-8',
    )
    return path


def test_a_file_that_leaves_the_arena_and_prints_a_clean_summary_fails(tmp_path) -> None:
    """The verdict comes from the simulator's counters and recorded poses, never from what the file prints."""
    report = check(lying_file(tmp_path), seeds=1, initializer_seeds=1)
    assert not report.passed
    bundled = report.runs[0]
    counted, recounted = bundled.counted, bundled.recounted
    assert counted is not None and counted.outside > 0 and counted == recounted  # V2's counters, recounted alike
    assert bundled.record is not None and bundled.record.experiment_steps == STEPS_OUTSIDE
    assert f'bundled seed 0: the simulator counted 0 pair-steps too close, {counted.outside} steps outside' in (
        '\n'.join(report.problems)
    )
    assert "bundled seed 0: not every robot ended past the tube's exit" in '\n'.join(report.problems)
    for run in report.runs:  # the PyPI simulator too, when installed: its own counters and the recount
        assert not run.ok and run.counted is not None and run.counted.outside > 0
        assert run.recounted is not None and run.recounted.outside > 0 and run.recounted.too_close == 0
