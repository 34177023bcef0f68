"""The single-file submission: reproducible, server-safe, accepted by both simulators, fast enough."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

from submission import runtime
from submission.builder import SubmissionError, build
from submission.check import check, imported_modules, static_check
from vtube_planning import SceneError, load_scene

ROOT = Path(__file__).resolve().parents[2]
SCENES = ('robotarium_trapezoid', 'robotarium_curve')


def data_of(source: str) -> dict:
    namespace: dict = {}
    exec(compile(source, 'submission', 'exec'), namespace)  # defines DATA and functions; runs nothing
    return namespace['DATA']


@pytest.mark.parametrize('scene', SCENES)
def test_committed_submission_equals_a_fresh_build(scene: str) -> None:
    committed = (ROOT / 'submission' / f'vtube_{scene}.py').read_text(encoding='utf-8')
    assert build(scene).source == committed, f'rebuild with: vtube submission build {scene} --out submission/vtube_{scene}.py'


@pytest.mark.parametrize('scene', SCENES)
def test_submission_imports_only_what_the_server_has_and_parses_as_python_310(scene: str) -> None:
    source = (ROOT / 'submission' / f'vtube_{scene}.py').read_text(encoding='utf-8')
    ast.parse(source, feature_version=(3, 10))
    assert static_check(source) == []
    assert imported_modules(source) <= {'__future__', 'math', 'numpy', 'json', 'os', 'time', 'rps'}
    assert static_check(source + '\nimport cvxpy\nfrom rosbags.highlevel import AnyReader\n') == ['cvxpy', 'rosbags']


@pytest.mark.parametrize('scene', SCENES)
def test_committed_submission_passes_the_preflight_on_both_simulators(scene: str) -> None:
    pytest.importorskip('rps.robotarium')  # the PyPI simulator (test extra)
    report = check(ROOT / 'submission' / f'vtube_{scene}.py', seeds=2)
    assert [run.backend for run in report.runs] == ['bundled', 'bundled', 'pypi']
    for run in report.runs:
        assert run.ok, (run.backend, run.seed, run.summary, run.stderr_tail)
        assert run.summary['min_center_distance_m'] > 0.135
    assert report.passed and report.robots == 6 and report.declare_duration_s >= 30


def test_saved_arrays_load_without_pickle(tmp_path, monkeypatch) -> None:
    import importlib
    import sys

    from robotarium_exp.rps import robotarium as ours
    from robotarium_exp.rps_alias import MODULES

    for suffix in MODULES:  # `import rps...` inside the runtime resolves to the bundled simulator, for this test only
        monkeypatch.setitem(sys.modules, 'rps' + suffix, importlib.import_module('robotarium_exp.rps' + suffix))

    class Module:  # robots placed at the initial conditions
        Robotarium = ours.ClassicRobotarium

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv('VTUBE_HEADLESS', '1')
    summary = runtime.run(data_of(build('robotarium_curve').source), Module, max_steps=150)
    poses = np.load(tmp_path / 'vtube_poses.npy', allow_pickle=False)
    assert poses.shape == (summary['steps'], 3, 6)
    for name in ('t', 'dxu', 'r_a', 'l', 'density', 'barrier_correction'):
        assert np.load(tmp_path / f'vtube_{name}.npy', allow_pickle=False).shape[0] == summary['steps']


def test_sampled_tube_matches_the_exact_projection() -> None:
    for scene_name in SCENES:
        scene = load_scene(scene_name)
        tube = runtime.SampledTube(data_of(build(scene_name).source)['tube'])
        rng = np.random.default_rng(0)
        l = rng.uniform(0.0, scene.tube.length_m, 500)
        y = rng.uniform(-1, 1, 500) * scene.tube.half_width(l)
        points = (scene.tube.center_at(l) + y[:, None] * scene.tube.normal(l)).T
        got = tube.project(points)
        # a 1 cm polyline: a point at offset y from a bend of curvature kappa lands up to |y| kappa h / 2 away
        # along a chord of length h: 0.5 m x 1.07 / m x 0.01 m / 2 = 2.7 mm at most on these tubes
        worst = 0.5 * float(np.abs(scene.tube.curvature(np.linspace(0, scene.tube.length_m, 2000))).max()) * 0.01 / 2
        assert np.abs(got['l'] - l).max() <= worst + 2e-5  # + the data's six significant digits
        assert np.all(np.abs(got['y'] - y) <= 2e-4)


@pytest.mark.parametrize(
    ('scene', 'error', 'match'),
    [
        ('robotarium_ellipse', SceneError, "unknown scene 'robotarium_ellipse'"),
        ('A', SubmissionError, 'does not fit the Robotarium arena'),
    ],
)
def test_bad_builder_input(scene: str, error: type, match: str) -> None:
    with pytest.raises(error, match=match):
        build(scene)


def test_too_many_robots(tmp_path) -> None:
    text = (ROOT / 'vtube_planning' / 'scenes' / 'robotarium_trapezoid.toml').read_text()
    path = tmp_path / 'crowd.toml'
    path.write_text(text.replace('n_robots = 6', 'n_robots = 24'))
    with pytest.raises(SubmissionError, match='has 24 robots; the Robotarium runs at most 20'):
        build(path)
