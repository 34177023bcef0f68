"""``vtube demo``: each stage under its title as its own command shows it, and the first failure ends it (stages
constructed here; the real demo: ``tests/integration/test_demo.py``)."""

from __future__ import annotations

from pathlib import Path

from vtube import pipeline
from vtube.cli.app import main
from vtube.cli.command import View
from vtube.cli.demo import FLIGHT_MODEL, RUN_TITLE, _titled, demo_view
from vtube.cli.simulate import simulate_view
from vtube.cli.submission import build_view

from .test_analyze import analysed
from .test_simulate import metrics, simulated
from .test_submission import GOOD, SUB, report


def test_a_stage_is_shown_under_its_title_and_a_failed_one_stops_the_demo() -> None:
    assert _titled('plan', View(('a',))) == View(('', '== plan ==', 'a'))
    failed = _titled('build', View(('b',), {'x': 1}, exit_code=1))
    assert failed.exit_code == 1 and failed.error == 'the demo stopped at "build"' and failed.data is None


def test_the_stages_in_order_each_as_its_command_shows_it() -> None:
    built = pipeline.WrittenSubmission(SUB, Path('s.py'), report(GOOD))
    stages = [
        simulated(metrics()),
        simulated(metrics(), planned=False),
        built,
        pipeline.Returned(Path('r'), Path('r/log.txt'), True),
        analysed(),
    ]
    views = list(demo_view(iter(stages)))
    titles = [view.lines[1] for view in views[:4]]
    assert titles == [
        '== simulate with planning ==',
        '== simulate without planning ==',
        '== build and check the submission ==',
        f'== {RUN_TITLE} ==',
    ]
    assert views[2].lines[2:] == build_view(built).lines and all(view.exit_code == 0 for view in views)
    assert views[4].lines[0].startswith('analysis of ros bag b.mcap in scene robotarium_curve')
    bad = list(demo_view(iter([pipeline.Returned(Path('r'), Path('r/log.txt'), False)])))
    assert bad[0].exit_code == 1 and bad[0].error == 'the submission failed on the bundled simulator; see r/log.txt'


def test_the_demo_command_renders_until_the_first_failure(tmp_path, monkeypatch, capsys) -> None:
    told = []

    def demo(out, *, progress):
        told.append(out)
        yield simulated(metrics())
        yield pipeline.Returned(Path('r'), Path('r/log.txt'), False)
        yield analysed()  # never reached: the run failed

    monkeypatch.setattr(pipeline, 'demo', demo)
    assert main(['demo', '--out', str(tmp_path / 'd')]) == 1
    captured = capsys.readouterr()
    assert told == [tmp_path / 'd'] and '== simulate with planning ==' in captured.out
    assert 'analysis of' not in captured.out and captured.err.startswith('error: the submission failed')


def test_each_simulation_says_its_flight_model_differs_from_the_robotarium_run() -> None:
    views = list(demo_view(iter([simulated(metrics()), simulated(metrics(), planned=False)])))
    for view in views:
        assert view.lines[-1] == FLIGHT_MODEL and "the paper's single integrator" in FLIGHT_MODEL
        assert 'barrier certificate' in FLIGHT_MODEL
    assert views[0].lines[2:-1] == simulate_view(simulated(metrics())).lines
