"""``vtube demo``: the whole way, plan to report, on the bundled simulator, run once (``demo_run``) and shared by
every test of it and of the submission it builds and checks (scene robotarium_curve, planned): the one built file
whose preflight the suite runs. One file, so that pytest-xdist (``--dist loadfile``) runs the demo once."""

from __future__ import annotations

import contextlib
import io
import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from robotarium_exp.experiment import initial_conditions, run_experiment
from robotarium_exp.spec import ROBOTARIUM
from submission.builder import BUILD_STAMP
from submission.declaration import Declaration
from vtube.cli.app import main
from vtube.cli.demo import FLIGHT_MODEL
from vtube.pipeline import (
    DEMO_SCENE,
    Analysed,
    Planned,
    Returned,
    Simulated,
    WrittenSubmission,
)
from vtube.starts import ROBOTARIUM_START
from vtube_planning.swarm.metrics import passage_metrics

ROOT = Path(__file__).resolve().parents[2]

CHECK_SEEDS = 1
"""Bundled runs of the demo's preflight (the demo itself asks for 2; one more seed of the same file adds no check)."""
INITIALIZER_SEEDS = 1
"""V2's initializer alone in the demo's preflight (the demo asks for 20: the same run repeated for a quantile)."""
CHECK_MODELS = ('ideal', 'fitted')
"""The testbed models of the demo's preflight: the two that decide the verdict (the stress model, fitted:2, is
exercised by the unit tests of the check with its runs stubbed)."""


@dataclass(frozen=True)
class DemoRun:
    """``vtube demo`` run once: its exit code, what it printed (stdout, stderr), its folder and each stage's result."""

    code: int
    out: str
    err: str
    folder: Path
    stages: tuple[Any, ...]

    def stage(self, kind: type) -> Any:
        """The first stage of a type (``pipeline.Planned``, ``WrittenSubmission``, ...)."""
        return next(stage for stage in self.stages if isinstance(stage, kind))


@pytest.fixture(scope='module')
def demo_run(tmp_path_factory: pytest.TempPathFactory) -> DemoRun:
    """``vtube demo`` in this process, its stages recorded as they end; the submission's preflight with
    :data:`CHECK_SEEDS`, :data:`INITIALIZER_SEEDS` and :data:`CHECK_MODELS` (the only change to the demo: fewer
    repetitions)."""
    from vtube import pipeline
    from vtube.cli.app import main

    folder = tmp_path_factory.mktemp('demo') / 'demo'
    stages: list[Any] = []
    demo, build_submission = pipeline.demo, pipeline.build_submission

    def recorded(out: Path, **kwargs: Any) -> Any:
        for stage in demo(out, **kwargs):
            stages.append(stage)
            yield stage

    def fewer_seeds(*args: Any, **kwargs: Any) -> Any:
        fewer = {'seeds': CHECK_SEEDS, 'initializer_seeds': INITIALIZER_SEEDS, 'testbed_models': CHECK_MODELS}
        return build_submission(*args, **(kwargs | fewer))

    out, err = io.StringIO(), io.StringIO()
    with pytest.MonkeyPatch.context() as patch, contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        patch.setattr(pipeline, 'demo', recorded)
        patch.setattr(pipeline, 'build_submission', fewer_seeds)
        code = main(['demo', '--out', str(folder)])
    return DemoRun(code, out.getvalue(), err.getvalue(), folder, tuple(stages))


def test_the_demo_runs_every_stage_and_reports_no_collision(demo_run) -> None:
    assert demo_run.code == 0, demo_run.err
    kinds = [type(stage) for stage in demo_run.stages]
    assert kinds == [Planned, Simulated, Simulated, WrittenSubmission, Returned, Analysed]
    assert [stage.result.planned for stage in demo_run.stages[1:3]] == [True, False]
    report = (demo_run.folder / 'report' / 'report.md').read_text()
    assert '| collision pairs | 0 |' in report and 'paths.png' in report
    # issue 49: the planned simulation's passing time beside the returned run's, as `simulate` printed it, and the
    # closest approach of the passage apart from the parking's
    simulated = demo_run.stages[1].result.metrics.passing_time_s
    row = next(line for line in report.splitlines() if line.startswith('| passing time [s] |'))
    assert row.split(' | ')[-1].rstrip(' |') == f'{simulated:.2f}' and '–' not in row
    comparison = demo_run.stage(Analysed).comparison
    assert comparison is not None and comparison.metrics.tube is not None
    assert comparison.metrics.tube.passage.passing_time_s == pytest.approx(simulated, abs=1e-6)  # ns stamps
    assert '| minimum distance up to the last exit (passage) [m] |' in report
    assert 'one robot having been seen before it' not in report
    titles = [line for line in demo_run.out.splitlines() if line.startswith('== ')]
    assert titles == [
        '== plan ==',
        '== simulate with planning ==',
        '== simulate without planning ==',
        '== build and check the submission ==',
        '== run the submission on the bundled simulator, as the testbed would, and analyse what it returns ==',
    ]
    assert demo_run.stage(Returned).ok and 'error:' not in demo_run.err


def test_the_returned_file_flies_the_bundled_experiment_and_compare_writes_the_table(
    demo_run, tmp_path, capsys, monkeypatch
) -> None:
    """``vtube robotarium compare`` flies the bundled experiment of the demo's scene and plan on V2's seed-0 draws:
    the built file that the demo ran as the testbed would flies the same poses."""
    import robotarium_exp.compare as compare_module

    flown = []

    def kept(*args, **kwargs):
        flown.append(run_experiment(*args, **kwargs))
        return flown[-1]

    monkeypatch.setattr(compare_module, 'run_experiment', kept)
    assert main(['robotarium', 'compare', DEMO_SCENE, '--seeds', '1', '--out', str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert '| measure | planned | unplanned |' in out and '| expansion starts [s] |' in out
    rows = json.loads((tmp_path / f'compare_{DEMO_SCENE}.json').read_text())
    assert [row['planned'] for row in rows] == [True, False]
    assert rows[1]['expansion_start_s'] is None and rows[0]['expansion_start_s'] > 0
    table = (tmp_path / f'compare_{DEMO_SCENE}.md').read_text()
    assert table.startswith(f'scene {DEMO_SCENE}, V2 initialization seeds 0-0, mean')
    assert (
        '| planned - unplanned, same seeds | verdict |' in table
        and 'The runs were made by `vtube robotarium compare' in table
    )

    experiment, planned = flown[0], demo_run.stage(Planned)
    assert experiment.planned and planned.scene.name == DEMO_SCENE
    folder = demo_run.stage(Returned).folder
    positions, t = np.load(folder / 'vtube_positions_m.npy'), np.load(folder / 'vtube_t_s.npy')
    tube = planned.scene.tube
    robots = [tube.project(p) for p in positions]
    returned = passage_metrics(
        t,
        positions,
        np.array([p.l_m for p in robots]),
        np.array([p.clearance_m for p in robots]),
        tube.length_m,
        collision_distance_m=2 * planned.scene.swarm.r_p_m,
        body_radius_m=0.5 * ROBOTARIUM.robot_diameter_m,
    )
    mine = experiment.metrics
    assert returned.passing_time_s == pytest.approx(mine.passing_time_s, rel=0.01)
    assert returned.min_distance_m == pytest.approx(mine.min_distance_m, abs=0.005)
    assert returned.tube_violation_steps == pytest.approx(mine.tube_violation_steps, rel=0.05)
    np.testing.assert_allclose(positions, experiment.arrays['positions_m'], atol=1e-9)  # in fact, the same trajectory
    # `vtube analyze` of the returned folder (the demo's last stage) times the flight from the start it recorded
    analysed = demo_run.stage(Analysed).data.metrics
    meta = json.loads((folder / 'vtube_meta.json').read_text())
    assert meta['flight_start']['iteration'] == meta['iterations'] - meta['steps'] + 1 > 0  # after V2's initialization
    assert analysed.source['flight_start']['t_s'] == 0.0
    assert analysed.tube.passage.start.startswith('start recorded by the flight')
    assert analysed.tube.passage.passing_time_s == pytest.approx(mine.passing_time_s, rel=0.01)
    assert analysed.closest.min_distance_m == pytest.approx(mine.min_distance_m, abs=0.005)
    assert analysed.tube.tube_violation_steps == pytest.approx(mine.tube_violation_steps, rel=0.05)
    assert analysed.tube.body_radius_m == 0.5 * ROBOTARIUM.robot_diameter_m


def _unstamped(source: str) -> str:
    """The file without its build stamp, and without the plan file its rebuild command names (the demo's plan is
    a file in its folder; the committed file was built planning the scene itself, to the same plan)."""
    lines = (line for line in source.splitlines() if not line.startswith(BUILD_STAMP))
    return '\n'.join(re.sub(r' --plan \S+', '', line) if 'vtube submission build' in line else line for line in lines)


def test_the_demos_submission_is_the_committed_file_but_for_its_declaration(demo_run) -> None:
    """So its preflight below is the preflight of the committed robotarium_curve flight (data and code)."""
    written = demo_run.stage(WrittenSubmission)
    committed = (ROOT / 'submissions' / 'vtube_robotarium_curve.py').read_text(encoding='utf-8')
    built = written.path.read_text(encoding='utf-8')
    recorded = Declaration.from_header(committed)
    assert recorded is not None and written.declaration is not None
    mine = '\n'.join(written.declaration.header_lines(6))
    assert mine in built
    assert _unstamped(built.replace(mine, '\n'.join(recorded.header_lines(6)))) == _unstamped(committed)


def test_the_demos_submission_passes_the_preflight_on_both_simulators(demo_run) -> None:
    pytest.importorskip('rps.robotarium')  # the PyPI simulator (test extra)
    report = demo_run.stage(WrittenSubmission).report
    assert [(run.backend, run.model) for run in report.runs] == [
        *[('bundled', model) for model in CHECK_MODELS for _ in range(CHECK_SEEDS)],
        ('pypi', 'ideal'),
    ]
    for run in report.runs:
        assert run.ok, (run.label, run.problems, run.stderr_tail)
        assert run.min_center_distance_m > 0.135
    assert report.passed and report.robots == 6
    assert [(m.model, m.runs, m.clean) for m in report.margins] == [(m, CHECK_SEEDS, CHECK_SEEDS) for m in CHECK_MODELS]
    assert all(m.wall_steps == 0 and m.min_distance_m > 0.135 for m in report.margins)
    fitted = report.runs[CHECK_SEEDS]  # the fitted model flew: not the ideal run's poses
    assert not np.array_equal(fitted.record.poses[:100], report.runs[0].record.poses[:100])
    declared = report.declaration
    assert declared is not None and report.initializer is not None and report.initializer.runs == INITIALIZER_SEEDS
    assert declared.duration_s >= max(report.initializer.durations_s) + declared.experiment_s - 10
    for run in report.runs:  # every checked run fits the verifier's 1.5 x the declaration
        assert run.duration_s <= 1.5 * declared.duration_s
    # the committed file's header (200 initializer seeds, 3 bundled runs) covers what these seeds derive
    committed = Declaration.from_header((ROOT / 'submissions' / 'vtube_robotarium_curve.py').read_text())
    assert committed is not None and committed.duration_s >= declared.duration_s


def test_the_build_prints_the_verdict_and_the_header_records_the_declaration(demo_run) -> None:
    written = demo_run.stage(WrittenSubmission)
    text = demo_run.out
    assert 'verdict                PASS' in text and 'declare                6 robots' in text
    declared = text.split('the header records the declaration: 6 robots, ')[1].split(' s')[0]
    assert int(declared) == written.declaration.duration_s
    assert f'Declare on the web form: 6 robots and {declared} s' in written.path.read_text()


def test_both_sides_of_the_comparison_start_from_the_same_formation(demo_run) -> None:
    """Like with like: both simulations start exactly at the submission's initial conditions (the robots' centres),
    and the returned flight starts where V2's initializer leaves them: within its 0.05 m of those poses, plus at most
    one period at v_max before the first record."""
    scene = demo_run.stage(Planned).scene
    start = np.array(initial_conditions(scene)[:2])
    flown = [stage for stage in demo_run.stages if isinstance(stage, Simulated)]
    for stage in flown:
        np.testing.assert_array_equal(stage.result.positions_m[0], start)
        assert stage.start == ROBOTARIUM_START
    returned = np.load(demo_run.stage(Returned).folder / 'vtube_positions_m.npy')[0]
    reach = 0.05 + scene.swarm.v_max_mps * ROBOTARIUM.time_step_s
    assert np.all(np.hypot(*(returned - start)) <= reach)
    assert demo_run.out.count(FLIGHT_MODEL) == 2 and demo_run.out.count(f'start              {ROBOTARIUM_START}') == 2
    # the planned flight passes sooner than the unplanned one from the same formation (the README's figures)
    assert flown[0].result.metrics.passing_time_s < flown[1].result.metrics.passing_time_s


def test_the_demos_reduced_declaration_marks_its_file_not_for_upload(demo_run) -> None:
    """The demo declares from fewer initializer seeds than a full build: its header and its output say NOT FOR
    UPLOAD and give the command that builds the file to upload; the committed file, a full build, says nothing."""
    written = demo_run.stage(WrittenSubmission)
    assert written.declaration is not None and not written.declaration.for_upload
    header = written.path.read_text(encoding='utf-8').split('"""')[1]
    assert header.index('NOT FOR UPLOAD: this duration rests on') < header.index('Declare on the web form')
    command = f'vtube submission build {DEMO_SCENE} --out experiment.py'
    assert f'Build the file to upload with `{command}`.' in demo_run.out and 'NOT FOR UPLOAD' in demo_run.out
    assert 'NOT FOR UPLOAD' not in (ROOT / 'submissions' / 'vtube_robotarium_curve.py').read_text(encoding='utf-8')
