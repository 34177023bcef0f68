"""The single-file submission: reproducible, server-safe, accepted by both simulators, fast enough."""

from __future__ import annotations

import functools
import inspect
from pathlib import Path

import numpy as np
import pytest

import submission.builder as builder_module
from robotarium_exp.initializer import InitializerSample
from robotarium_exp.rps.testbed_model import FITTED_VERSION
from robotarium_exp.scene import load_scene
from submission.builder import BUILD_STAMP, UNDECLARED, Submission, SubmissionError, build, build_declared, write
from submission.check import CheckReport, imported_modules
from submission.declaration import FULL_BUILD_INITIALIZER_SEEDS, Declaration, declare
from submission.delay_margin import LADDER, MIN_SEEDS
from vtube_planning import SceneError
from vtube_planning.onboard import PlanProfile, SampledTube, StepParams, SwarmStep
from vtube_planning.planning.plan import Plan
from vtube_planning.planning.planner import plan_convex

ROOT = Path(__file__).resolve().parents[3]
SCENES = ('robotarium_trapezoid', 'robotarium_curve')
COMMITTED = (*SCENES, 'robotarium_trapezoid_20', 'robotarium_curve_20')
"""The scenes whose submissions are committed in ``submissions/`` (as ``vtube_SCENE.py``)."""


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


@functools.cache
def unplanned(scene: str) -> Submission:
    """The unplanned build of a shipped scene (built once per test session)."""
    return build(scene, None)


def planned(path: str | Path) -> str:
    """The source of a planned build of a scene file or shipped scene."""
    scene = load_scene(path)
    return build(scene, plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)).source


def variant(tmp_path: Path, scene: str, control_line: str) -> Path:
    """A copy of a shipped scene with one more line under [control], as a user would write it."""
    text = (ROOT / 'robotarium_exp' / 'scenes' / f'{scene}.toml').read_text(encoding='utf-8')
    path = tmp_path / f'{scene}_variant.toml'
    key = control_line.split('=')[0].strip()
    lines = [line for line in text.splitlines() if not line.startswith(f'{key} =')]  # the variant's value wins
    text = '\n'.join(lines)
    text = (
        text.replace('[control]', f'[control]\n{control_line}')
        if '[control]' in text
        else f'{text}\n[control]\n{control_line}\n'
    )
    path.write_text(text, encoding='utf-8')
    return path


@pytest.mark.parametrize('control_line', ['law = "practical"', 'feedforward = false'])
def test_the_inlined_step_is_the_library_step(tmp_path, control_line: str) -> None:
    """The submission's own SwarmStep (its inlined source, its rounded data) commands what the package's does."""
    ns = namespace_of(planned(variant(tmp_path, 'robotarium_curve', control_line)))
    data = ns['DATA']
    assert ns['SwarmStep'] is not SwarmStep  # really the file's copy
    key, value = (part.strip().strip('"') for part in control_line.split('='))
    assert str(data['step'][{'law': 'law', 'feedforward': 'feedforward'}[key]]).lower() == value  # the variant's

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


@pytest.mark.parametrize('scene', COMMITTED)
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


@pytest.mark.parametrize('scene', COMMITTED)
def test_every_committed_submission_records_its_delay_margin(scene: str) -> None:
    """Its header names the margin, the seeds (at least the minimum a margin rests on) and the model version."""
    source = (ROOT / 'submissions' / f'vtube_{scene}.py').read_text(encoding='utf-8')
    recorded = Declaration.from_header(source)
    assert recorded is not None and recorded.delay_margin is not None, (
        f'rebuild with: vtube submission build {scene} --out submissions/vtube_{scene}.py --margin-seeds {MIN_SEEDS}'
    )
    margin = recorded.delay_margin
    assert margin.seeds >= MIN_SEEDS and margin.model_version == FITTED_VERSION
    assert [rung.multiple for rung in margin.rungs] == list(LADDER[: len(margin.rungs)])
    assert all(rung.runs == margin.seeds for rung in margin.rungs)
    assert f'{margin.seeds} seeds at each multiple' in source and 'runs may fail' in source


def _unstamped(source: str) -> str:
    """A built file without its build stamp (when and by which command: the one line that differs by build)."""
    return '\n'.join(line for line in source.splitlines() if not line.startswith(BUILD_STAMP))


def test_sampled_tube_matches_the_exact_projection() -> None:
    for scene_name in SCENES:
        scene = load_scene(scene_name)
        tube = SampledTube(**data_of(unplanned(scene_name).source)['tube'])
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
        ('A', SubmissionError, 'does not fit the Robotarium: the tube'),
    ],
)
def test_bad_builder_input(scene: str, error: type, match: str) -> None:
    with pytest.raises(error, match=match):
        build(scene, None)


def test_too_many_robots(tmp_path) -> None:
    text = (ROOT / 'robotarium_exp' / 'scenes' / 'robotarium_trapezoid.toml').read_text()
    path = tmp_path / 'crowd.toml'
    path.write_text(text.replace('n_robots = 6', 'n_robots = 24'))
    with pytest.raises(SubmissionError, match='24 robots; the testbed has 20: use 1 to 20'):
        build(path, None)


def test_the_builder_refuses_initial_conditions_that_can_stall_the_initializer(monkeypatch) -> None:
    """The old order (robot 1 in the middle of the front row) left trapezoid seed 38 stuck for good in V2."""
    from robotarium_exp import design

    monkeypatch.setattr(design, 'order_for_v2_initializer', lambda ic: list(range(ic.shape[1])))
    with pytest.raises(
        SubmissionError, match=r"'robotarium_trapezoid' does not fit .*robots 0 and 1 start 0.40 m apart"
    ):
        build('robotarium_trapezoid', None)


def test_an_unplanned_file_carries_no_plan_and_its_header_describes_none() -> None:
    built = unplanned('robotarium_curve')
    header = built.source[: built.source.index('from __future__')]
    assert data_of(built.source)['plan'] is None and not built.planned
    assert 'No plan: constant forward speed 0.08 m/s and constant avoidance radius 0.3 m.' in header
    assert 'Plan:' not in header and 'certificate' not in header and '--no-planning' in header
    planned_header = planned('robotarium_curve')
    assert 'Plan: convex slowness method, ' in planned_header[: planned_header.index('from __future__')]


def test_the_header_lists_the_imports_read_from_the_file() -> None:
    source = unplanned('robotarium_trapezoid').source
    header = ' '.join(source[: source.index('from __future__')].split())
    found = imported_modules(source) - {'__future__'}
    assert 'scipy' in found and 'numpy' in found and 'rps' in found
    packages = sorted(found & {'numpy', 'scipy', 'rps'})
    listed = ', '.join("the testbed's rps" if m == 'rps' else m for m in packages)
    standard = ', '.join(sorted(found - {'numpy', 'scipy', 'rps'}))
    assert f'It imports {listed} and, from the standard library, {standard}.' in header


def test_the_declaration_is_stamped_into_the_built_file() -> None:
    """One build: the declaration replaces the header's request for one, and nothing else changes."""
    submission = unplanned('robotarium_trapezoid')
    declaration = declare(InitializerSample((20.0, 35.5), ()), experiment_s=61.3)
    declared = submission.declared(declaration)
    assert UNDECLARED in submission.source and UNDECLARED not in declared.source
    assert Declaration.from_header(declared.source) == declaration
    before, after = submission.source.split(UNDECLARED)
    assert declared.source.startswith(before) and declared.source.endswith(after)
    with pytest.raises(SubmissionError, match='already records a declaration'):
        declared.declared(declaration)


def test_build_declared_stamps_what_the_check_derived_into_the_file_it_checked(tmp_path, monkeypatch) -> None:
    """One build, one check (stubbed here: the real one is in tests/integration/test_preflight.py), of a file in a
    private folder: ``--out`` is written only when the check passed; a failed build goes beside it."""
    declaration = declare(InitializerSample((20.0, 35.5), ()), experiment_s=61.3)
    checked: list[tuple[Path, str, dict]] = []

    def check(path, **options):
        checked.append((Path(path), Path(path).read_text(encoding='utf-8'), options))
        return CheckReport(str(path), declaration=declaration, declaration_problem=verdict.pop())

    monkeypatch.setattr(builder_module, 'check', check)
    verdict = ['', 'the header records 10 s']  # popped from the end: the first check fails, the second passes
    monkeypatch.setattr(CheckReport, 'passed', property(lambda self: not self.declaration_problem))
    scene = load_scene('robotarium_trapezoid')
    path = tmp_path / 'deep' / 'sub.py'
    failed, report, written = build_declared(scene, None, path, seeds=2, initializer_seeds=7)
    assert not report.passed and not path.exists() and written == tmp_path / 'deep' / 'sub.failed.py'
    assert report.path == str(written) and failed.source == written.read_text() and UNDECLARED in failed.source
    assert checked[0][0].parent != path.parent and checked[0][0].name == 'sub.py' and UNDECLARED in checked[0][1]
    assert checked[0][2]['seeds'] == 2 and checked[0][2]['initializer_seeds'] == 7
    passed, _, written = build_declared(scene, None, path)
    assert written == path and Declaration.from_header(path.read_text()) == declaration
    assert passed.source == path.read_text() and UNDECLARED in checked[1][1]  # it checked the file before stamping
    before = path.read_text()
    verdict.append('fails')  # a declared file in place: a later build that fails leaves it as it was
    assert build_declared(scene, None, path)[2].name == 'sub.failed.py' and path.read_text() == before


def test_write_creates_the_folder(tmp_path) -> None:
    submission = Submission('print(1)\n', 'x', False, 1)
    assert write(submission, tmp_path / 'a' / 'b.py').read_text() == 'print(1)\n'


def test_a_preview_declaration_marks_the_file_not_for_upload_and_points_to_the_full_build() -> None:
    """Fewer initializer seeds than a full build: the header says NOT FOR UPLOAD above the declaration, and the
    command it points to ("Rebuild with") builds with the full build's seeds (the defaults)."""
    submission = unplanned('robotarium_trapezoid')
    preview = submission.declared(declare(InitializerSample((20.0, 35.5), ()), experiment_s=61.3))
    header = preview.source.split('"""')[1]
    assert header.index('NOT FOR UPLOAD: this duration rests on 2 initializer seeds') < header.index('Declare on')
    rebuild = header.split('Rebuild with:\n')[1].splitlines()[0]
    assert rebuild == '    vtube submission build robotarium_trapezoid --out FILE --no-planning'
    assert inspect.signature(build_declared).parameters['initializer_seeds'].default == FULL_BUILD_INITIALIZER_SEEDS
    full = declare(InitializerSample((20.0,) * FULL_BUILD_INITIALIZER_SEEDS, ()), experiment_s=61.3)
    assert 'NOT FOR UPLOAD' not in submission.declared(full).source


def test_hostile_titles_paths_and_commands_stay_text_in_a_file_that_compiles(tmp_path, monkeypatch) -> None:
    """Text from a scene file, its path and the command line can never end the docstring or become code."""
    import ast

    text = (ROOT / 'robotarium_exp' / 'scenes' / 'robotarium_trapezoid.toml').read_text()
    hostile = 'T"""; import os; os.system("echo pwned") #\\U\\x00 é'
    title = next(line for line in text.splitlines() if line.startswith('title'))
    folder = tmp_path / 'C:\\Users\\"""x'
    folder.mkdir()
    path = folder / 'trap.toml'
    path.write_text(text.replace(title, f"title = '''{hostile}'''"), encoding='utf-8')
    monkeypatch.setattr('sys.argv', ['vtube', 'submission', 'build', str(path), '--out', 'a"""b\\N{x}.py'])
    source = build(path, None).source
    tree = ast.parse(source)  # it compiles
    docstring = ast.get_docstring(tree, clean=False) or ''
    assert f"Scene 'trap': {hostile}. 6 robots" in docstring  # the title reads back as itself: text
    assert 'a"""b\\N{x}.py' in docstring and str(folder) in docstring  # the command and the path read back as typed
    calls = [n for n in ast.walk(tree) if isinstance(n, ast.Attribute) and n.attr == 'system']
    assert calls == [] and all('pwned' not in ast.unparse(node) for node in tree.body[1:])  # text only


def test_non_finite_flight_data_is_refused_before_a_file_exists(monkeypatch) -> None:
    from robotarium_exp.flight_data import FlightData

    real = FlightData.to_plain
    monkeypatch.setattr(FlightData, 'to_plain', lambda self: real(self) | {'constant_speed_mps': float('nan')})
    with pytest.raises(SubmissionError, match=r"the flight data holds nan at DATA\['constant_speed_mps'\]"):
        build('robotarium_trapezoid', None)


def test_the_rebuild_command_of_an_own_scene_file_and_plan_works_as_printed(tmp_path, monkeypatch) -> None:
    """Issue 49: the header's "Rebuild with" named an own scene file by its name (an unknown scene) and dropped
    --plan. It names the file and the plan by absolute path, so that it works from any folder, exactly as printed."""
    import shlex

    from vtube.cli.app import main

    own = tmp_path / 'mine' / 'my tube.toml'  # a space: quoted as the shell needs
    own.parent.mkdir()
    own.write_text((ROOT / 'robotarium_exp' / 'scenes' / 'robotarium_trapezoid.toml').read_text(), encoding='utf-8')
    monkeypatch.chdir(own.parent)
    assert main(['plan', own.name, '--out', 'plan']) == 0
    plan_file = Path('plan') / 'plan_my tube.npz'
    scene = load_scene(own.name)
    source = build(scene, Plan.load(plan_file, scene.tube), plan_file=plan_file).source
    rebuild = source.split('Rebuild with:\n')[1].splitlines()[0].strip()
    words = shlex.split(rebuild)
    assert words[:3] == ['vtube', 'submission', 'build'] and words[3] == str(own.resolve())
    assert words[words.index('--plan') + 1] == str(plan_file.resolve())
    monkeypatch.chdir(tmp_path)  # elsewhere: the command as printed, FILE given
    args = [*words[1 : words.index('FILE')], str(tmp_path / 'again.py'), *words[words.index('FILE') + 1 :]]
    assert main([*args, '--no-declare']) == 0
    again = (tmp_path / 'again.py').read_text(encoding='utf-8')
    assert again.split('DATA = ')[1] == source.split('DATA = ')[1]  # the same flight, from the same plan
