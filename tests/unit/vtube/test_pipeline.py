"""The pipeline's stages as a library: what each writes and returns, how it reports progress and interruption,
and the demo's order and stops (figures stubbed where only their files matter; real ones in the integration
tests)."""

from __future__ import annotations

import os
import sys
from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from robotarium_exp.errors import AnalysisError
from robotarium_exp.experiment import initial_conditions
from robotarium_exp.scene import load_scene
from submission.builder import UNDECLARED
from vtube import pipeline, starts
from vtube.pipeline import (
    AnalysisOptions,
    Returned,
    SimulationInterrupted,
    WrittenSubmission,
    analyse_data,
    build_submission,
    no_progress,
    plan_for,
    plan_scene,
    run_on_bundled,
    simulate_scene,
)
from vtube_planning.errors import VtubeError
from vtube_planning.swarm.formation import as_positions
from vtube_planning.swarm.simulate import SimConfig

SHORT = SimConfig(time_limit_s=0.4)


@pytest.fixture
def no_figures(monkeypatch) -> list[str]:
    """Every figure of :mod:`vtube_planning.plots` stubbed: ``save_figure`` writes the file's name only."""
    made: list[str] = []

    def save_figure(figure, path):
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        Path(path).write_text(figure)
        made.append(Path(path).name)
        return Path(path)

    plots = pipeline.plots
    for name in ('plan_figure', 'snapshots_figure', 'distance_figure', 'tracking_figure'):
        monkeypatch.setattr(plots, name, lambda *args, name=name, **kwargs: name)
    monkeypatch.setattr(plots, 'save_figure', save_figure)
    return made


def test_plan_for_plans_or_reads_a_file_made_for_this_scene(tmp_path, no_figures) -> None:
    scene = load_scene('robotarium_trapezoid')
    planned = plan_scene('robotarium_trapezoid', tmp_path)
    assert planned.plan_file == tmp_path / 'plan_robotarium_trapezoid.npz' and planned.method == 'convex'
    assert planned.scene_copy.read_text() == scene.text and no_figures == ['plan_robotarium_trapezoid.png']
    assert planned.plan.provenance['scene_sha256'] and planned.plan.provenance['command']
    fresh = plan_for(scene)
    np.testing.assert_array_equal(plan_for(scene, plan_file=planned.plan_file).speed_mps, fresh.speed_mps)
    with pytest.raises(VtubeError, match='other swarm parameters'):
        plan_for(scene, replace(scene.swarm, n_robots=5), planned.plan_file)
    coarse = plan_scene('robotarium_trapezoid', tmp_path / 'c', method='polynomial', grid_step_m=0.05)
    assert coarse.plan.options.grid_step_m == 0.05 and coarse.method == 'polynomial'


def test_simulate_writes_the_log_figures_and_scene_copy_and_tells_its_progress(tmp_path, no_figures) -> None:
    opened, ticks = [], []

    def progress(what, unit):
        opened.append((what, unit))
        return _ticks(ticks)

    flown = simulate_scene('A', tmp_path, n_robots=3, config=SHORT, progress=progress)
    names = [path.name for path in flown.written]
    assert names == [
        'sim_A_planned.npz',
        'sim_A_planned_snapshots.png',
        'sim_A_planned_distance.png',
        'sim_A_planned_tracking.png',
        'scene_A.toml',
    ]
    assert all(path.exists() for path in flown.written)
    assert flown.log == tmp_path / 'sim_A_planned.npz' and flown.swarm.n_robots == 3 and flown.result.planned
    assert flown.start == pipeline.GRID_START and flown.config == SHORT  # a paper scene: the simulator's grid
    assert opened == [('simulated', 's')] and ticks == sorted(ticks) and 0 < ticks[-1] <= 0.4 + 1e-9
    unplanned = simulate_scene('A', tmp_path, planning=False, n_robots=2, config=SHORT)
    assert [p.name for p in unplanned.written] == [
        'sim_A_unplanned.npz',
        'sim_A_unplanned_snapshots.png',
        'sim_A_unplanned_distance.png',
        'scene_A.toml',
    ]  # no plan: no tracking figure


def _ticks(ticks: list[float]):
    from contextlib import contextmanager

    @contextmanager
    def opened():
        yield ticks.append

    return opened()


def test_the_gif_is_drawn_with_its_frames_told(tmp_path, no_figures, monkeypatch) -> None:
    def animate(result, tube, path, *, progress):
        for i in range(3):
            progress(i, 3)
        Path(path).write_bytes(b'GIF89a')
        return Path(path)

    monkeypatch.setattr(pipeline.plots, 'animate', animate)
    opened: list[tuple[str, str]] = []
    ticks: list[float] = []

    def progress(what, unit):
        opened.append((what, unit))
        return _ticks(ticks)

    flown = simulate_scene('A', tmp_path, planning=False, n_robots=2, config=SHORT, animate=True, progress=progress)
    assert opened == [('simulated', 's'), ('GIF frames', 'frame')] and ticks[-3:] == [1, 2, 3]
    assert flown.written[-2].name == 'sim_A_unplanned.gif' and flown.written[-1].name == 'scene_A.toml'


def test_an_animation_is_a_gif(tmp_path) -> None:
    from vtube_planning.params import ControlParams
    from vtube_planning.plots import animate
    from vtube_planning.swarm.simulate import simulate

    scene = load_scene('A')
    result = simulate(
        scene.tube, replace(scene.swarm, n_robots=4), ControlParams(), plan=None, config=SimConfig(time_limit_s=1.0)
    )
    path = animate(result, scene.tube, tmp_path / 'run.gif', frames=4)
    assert path.read_bytes()[:6] == b'GIF89a'


def test_an_interrupted_simulation_says_where_its_steps_are(tmp_path, monkeypatch) -> None:
    def interrupted(*args, log_path, **kwargs):
        if flushed:
            Path(log_path).with_name(Path(log_path).stem + '.partial.npz').write_bytes(b'rows')
        raise KeyboardInterrupt

    monkeypatch.setattr(pipeline, 'simulate', interrupted)
    flushed = True
    with pytest.raises(SimulationInterrupted) as stop:
        simulate_scene('A', tmp_path, planning=False, config=SHORT)
    log = tmp_path / 'sim_A_unplanned.npz'
    partial = tmp_path / 'sim_A_unplanned.partial.npz'
    assert str(stop.value) == (
        f'interrupted: the steps flown so far are in {partial}; a finished log at {log} is left as it was.'
    )
    partial.unlink()
    flushed = False
    with pytest.raises(SimulationInterrupted, match='interrupted: nothing was flown yet;'):
        simulate_scene('A', tmp_path, planning=False, config=SHORT)


def test_a_submission_is_written_undeclared_or_built_declared(tmp_path, monkeypatch) -> None:
    written = build_submission('robotarium_trapezoid', tmp_path / 'a.py', planning=False, declare=False)
    assert written.report is None and written.declaration is None and UNDECLARED in written.path.read_text()
    assert written.submission.scene == 'robotarium_trapezoid' and not written.submission.planned
    calls = []

    def build_declared(
        scene, plan, out, *, seeds, initializer_seeds, testbed_models, margin_seeds, progress, seed_done, plan_file
    ):
        calls.append((scene.name, plan is None, out, seeds, initializer_seeds, testbed_models, margin_seeds))
        assert progress == told.append and seed_done is None  # the check's progress, passed through
        return written.submission, SimpleNamespace(passed=True, declaration='the declaration'), out

    monkeypatch.setattr(pipeline, 'build_declared', build_declared)
    told: list[str] = []
    declared = build_submission(
        'robotarium_trapezoid', tmp_path / 'b.py', planning=False, seeds=2, initializer_seeds=5, progress=told.append
    )
    assert calls == [('robotarium_trapezoid', True, tmp_path / 'b.py', 2, 5, ('ideal', 'fitted', 'fitted:2'), ())]
    build_submission(
        'robotarium_trapezoid', tmp_path / 'c.py', planning=False, margin_seeds=range(10), progress=told.append
    )
    assert calls[-1][-1] == range(10)  # the delay margin's seeds reach the check
    assert declared.declaration == 'the declaration' and declared.path == tmp_path / 'b.py'
    failed = WrittenSubmission(written.submission, tmp_path, SimpleNamespace(passed=False, declaration='x'))
    assert failed.declaration is None  # a file that failed its check records no declaration


def test_a_submission_runs_in_this_process_and_leaves_it_as_it_was(tmp_path) -> None:
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
    script.write_text('import sys\nsys.exit(3)\n')
    assert not run_on_bundled(script, tmp_path / 'exit').ok
    script.write_text('import sys\nsys.exit(0)\n')
    assert run_on_bundled(script, tmp_path / 'zero').ok


def test_a_plan_file_without_its_scene_is_refused(tmp_path) -> None:
    with pytest.raises(AnalysisError, match='a plan file needs the scene it was made for'):
        analyse_data([tmp_path], tmp_path / 'out', AnalysisOptions(plan_file=tmp_path / 'p.npz'))


def test_the_demo_runs_its_stages_in_order_and_stops_at_a_failure(tmp_path, monkeypatch) -> None:
    done: list[str] = []
    outcome = {'declaration': 'declared', 'ok': True}

    def stage(name, value):
        def run(*args, **kwargs):
            done.append(name if name != 'simulate' else f'simulate {kwargs.get("planning", True)}')
            return value(args, kwargs) if callable(value) else value

        return run

    planned = SimpleNamespace(plan_file=tmp_path / 'p.npz')
    flown = SimpleNamespace(log=tmp_path / 'log.npz')
    built = lambda args, kwargs: SimpleNamespace(declaration=outcome['declaration'], path=tmp_path / 's.py')
    monkeypatch.setattr(pipeline, 'plan_scene', stage('plan', planned))
    monkeypatch.setattr(pipeline, 'simulate_scene', stage('simulate', flown))
    monkeypatch.setattr(pipeline, 'build_submission', stage('build', built))
    ran = lambda args, kwargs: Returned(tmp_path / 'r', tmp_path / 'r' / 'log.txt', outcome['ok'])
    monkeypatch.setattr(pipeline, 'run_on_bundled', stage('run', ran))
    monkeypatch.setattr(pipeline, 'analyse_data', stage('analyse', 'analysed'))
    stages = list(pipeline.demo(tmp_path, progress=no_progress))
    assert done == ['plan', 'simulate True', 'simulate False', 'build', 'run', 'analyse'] and stages[-1] == 'analysed'
    done.clear()
    outcome['ok'] = False
    assert len(list(pipeline.demo(tmp_path))) == 5 and done[-1] == 'run'  # a failed run: nothing to analyse
    done.clear()
    outcome['declaration'] = None
    assert len(list(pipeline.demo(tmp_path))) == 4 and done[-1] == 'build'  # no declaration: not run


def test_a_robotarium_scene_is_simulated_from_its_flights_entry_formation(tmp_path, no_figures) -> None:
    """The hook gives a Robotarium scene's entry formation (for the swarm flown), None for a paper scene; the
    simulation starts exactly there unless its config gives positions."""
    paper = load_scene('A')
    assert starts.robotarium_start(paper, paper.swarm) is None
    scene = load_scene('robotarium_curve')
    four = replace(scene.swarm, n_robots=4)
    start = starts.robotarium_start(scene, four)
    assert start is not None
    np.testing.assert_array_equal(start, initial_conditions(replace(scene, swarm=four))[:2])
    inside = scene.tube.project(start)
    assert np.all(inside.clearance_m > 0) and np.all((inside.l_m > 0) & (inside.l_m < scene.tube.length_m))
    flown = simulate_scene('robotarium_curve', tmp_path, planning=False, n_robots=4, config=SHORT)
    np.testing.assert_array_equal(flown.result.positions_m[0], start)
    assert flown.start == starts.ROBOTARIUM_START and flown.config.initial_positions_m == as_positions(start)
    moved = replace(SHORT, initial_positions_m=start - 0.01)
    given = simulate_scene('robotarium_curve', tmp_path, planning=False, n_robots=4, config=moved)
    assert given.start == 'the given positions'
    np.testing.assert_array_equal(given.result.positions_m[0], start - 0.01)
