"""``vtube robotarium run|compare``: the views of a run and of a comparison, and compare's wiring (stubbed runs;
real runs in ``tests/integration``)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from types import SimpleNamespace

import robotarium_exp.compare as compare_module
from robotarium_exp.compare import ComparisonRow
from robotarium_exp.tracking import PhaseTracking, PlanTracking
from robotarium_exp.verdict import VerifierVerdict
from robotarium_exp.verifier import VerifierCounts
from tests.support.passage import metrics
from vtube.cli.app import main
from vtube.cli.robotarium import FLEW, Comparison, RobotariumRun, comparison_view, experiment_view
from vtube_planning.swarm.metrics import PassageMetrics


def run(
    counts: VerifierCounts, tracking: PlanTracking | None, passage: PassageMetrics | None = None, parked: bool = True
) -> RobotariumRun:
    barrier = SimpleNamespace(
        correction_mean_mps=0.0012,
        correction_max_mps=0.05,
        intervention_m=1.234,
        failures=0,
        band_share=0.995,
        band_share_held=0.9991,
        band_dropped_share=0.0004,
    )
    passage = metrics(tube_violation_steps=0, robots_outside=0, max_outside_m=0.0) if passage is None else passage
    result = SimpleNamespace(metrics=passage, barrier=barrier, completed=parked, errors=counts, duration_s=61.25)
    return RobotariumRun(
        scene=SimpleNamespace(name='robotarium_curve'),
        config=SimpleNamespace(planning=tracking is not None, barrier=True),
        result=result,
        verdict=VerifierVerdict(counts, 61.25),
        tracking=tracking,
        written=(Path('r/e.npz'), Path('r/e.png'), Path('r/s.toml')),
    )


def test_the_view_of_a_run_the_testbed_would_run() -> None:
    phase = PhaseTracking(100, 0.12, 0.3, 0.05, 0.1)
    tracked = PlanTracking(None, phase, PhaseTracking(0, None, None, None, None), phase, 4.0, None)
    view = experiment_view(run(VerifierCounts(0, 0, 0), tracked))
    assert view.lines[0] == (
        'Robotarium experiment, scene robotarium_curve, with planning, barrier on: would run on the Robotarium'
    )
    assert '  too close (pair-steps) 0' in view.lines and '  actuator-limit steps   0' in view.lines
    assert view.lines[4].startswith('  duration               61.2 s (initialization included: declare at least ')
    assert '  speed band             99.50 % of flying robot-steps in [v_min, v_max] (99.91 % where' in view.lines[9]
    tracking = [line for line in view.lines if 'tracking' in line]
    assert tracking == [
        '  tracking, approach     density error mean 12 % (max 30 %), speed error mean 5 %',
        '  tracking, narrow       density error mean 12 % (max 30 %), speed error mean 5 %',
    ]  # the phase without a step is left out
    assert '  expansion              starts at 4.0 s; the front reaches the narrowing at never' in view.lines
    assert view.exit_code == 0 and view.data['would_run'] and view.data['log'] == 'r/e.npz'
    assert view.lines[-2] == f'  flight                 {FLEW}' and 'failures' not in view.data
    assert view.data['errors'] == VerifierCounts(0, 0, 0).to_json() and view.data['duration_s'] == 61.25


def test_a_run_with_robots_too_close_would_not_run_and_fails() -> None:
    view = experiment_view(run(VerifierCounts(3, 0, 0), None))
    assert 'without planning' in view.lines[0] and view.lines[0].endswith('would NOT run on the Robotarium')
    assert view.exit_code == 1 and not any('tracking' in line or 'expansion' in line for line in view.lines)
    assert view.lines[-2] == (
        '  flight                 FAILED: the testbed would not run it (3 pair-steps of robots too close, 0 '
        'robot-steps outside the arena)'
    )


def test_a_run_the_testbed_would_run_fails_when_robots_do_not_pass_or_park_or_touch_the_walls() -> None:
    """The issue's N = 20 run: "would run on the Robotarium", passing time nan, parked: no, 14715 violations."""
    passage = metrics(
        passing_time_s=math.nan, completed=False, robots_passed=0, robots_counted=20, tube_violation_steps=0
    )
    view = experiment_view(run(VerifierCounts(), None, metrics(tube_violation_steps=14715, robots_outside=20)))
    assert view.lines[0].endswith(': would run on the Robotarium') and view.exit_code == 1
    assert view.data['failures'] == [
        'robot bodies were on the tube walls in 14715 robot-steps (20 robots, up to 0.013 m over)'
    ]
    view = experiment_view(run(VerifierCounts(), None, passage, parked=False))
    assert '  passing time           nan s; parked: no' in view.lines and view.exit_code == 1
    assert view.lines[-2] == (
        '  flight                 FAILED: 20 of 20 robots never passed the exit (no passing time); not every robot '
        'parked beyond the exit by the last step'
    )
    assert experiment_view(run(VerifierCounts(), None, parked=False)).exit_code == 1


def stubbed_rows(seeds: list[int], run_done, failed: tuple[int, bool] | None = None) -> list[ComparisonRow]:
    """Rows of a stubbed comparison; ``failed``: the (seed, planned) run that did not park."""
    values = dict.fromkeys(('passing_time_s', 'min_distance_m', 'intervention_m', 'band_percent'), 1.0)
    values |= {'tube_violation_steps': 0, 'approach_percent': None, 'dip_percent': None, 'testbed_errors': 0}
    values |= {'front_at_narrowing_s': 3.0}
    rows = []
    for seed in seeds:
        for planned in (True, False):
            failures = ('not every robot parked beyond the exit by the last step',) if failed == (seed, planned) else ()
            start = 2.0 if planned else None
            rows.append(ComparisonRow(seed=seed, planned=planned, expansion_start_s=start, failures=failures, **values))
            run_done()
    return rows


def test_compare_draws_its_runs_and_writes_the_table_and_rows(tmp_path, monkeypatch, capsys) -> None:
    """The runs stubbed (their loop is robotarium_exp's; the real one in tests/integration/test_demo.py)."""
    calls = []

    def compare(scene, plan, seeds, run_done=None, testbed_model='ideal'):
        calls.append((scene.name, plan.scene, seeds, testbed_model))
        return stubbed_rows(seeds, run_done)

    monkeypatch.setattr(compare_module, 'compare', compare)
    assert main(['robotarium', 'compare', 'robotarium_curve', '--seeds', '2', '--out', str(tmp_path / 'c')]) == 0
    assert calls == [('robotarium_curve', 'robotarium_curve', [0, 1], 'ideal')]
    out = capsys.readouterr().out
    assert out.startswith('scene robotarium_curve, V2 initialization seeds 0-1, mean [min, max]:\n| measure |')
    rows = json.loads((tmp_path / 'c' / 'compare_robotarium_curve.json').read_text())
    assert [row['planned'] for row in rows] == [True, False, True, False]
    table = (tmp_path / 'c' / 'compare_robotarium_curve.md').read_text()
    assert table.startswith('scene robotarium_curve, V2 initialization seeds 0-1, mean [min, max]:\n\n| measure |')
    assert '| expansion starts [s] | 2.0 [2.0, 2.0] | never |' in table
    assert '\n\n| planned - unplanned, same seeds | verdict |\n' in table  # then the paired claims


def test_compare_runs_exactly_the_seeds_of_a_range(tmp_path, monkeypatch, capsys) -> None:
    """``--seeds 3-4``: seeds 3 and 4, not 0..n-1; the table and the rows say which."""
    given = []

    def compare(scene, plan, seeds, run_done=None, testbed_model='ideal'):
        given.append(list(seeds))
        return stubbed_rows(seeds, run_done)

    monkeypatch.setattr(compare_module, 'compare', compare)
    assert main(['robotarium', 'compare', 'robotarium_curve', '--seeds', '3-4', '--out', str(tmp_path)]) == 0
    assert given == [[3, 4]]
    assert capsys.readouterr().out.startswith('scene robotarium_curve, V2 initialization seeds 3-4, mean')
    rows = json.loads((tmp_path / 'compare_robotarium_curve.json').read_text())
    assert [row['seed'] for row in rows] == [3, 3, 4, 4]
    assert (tmp_path / 'compare_robotarium_curve.md').read_text().startswith('scene robotarium_curve, V2 initial')
    assert main(['robotarium', 'compare', 'robotarium_curve', '--seeds', '10,3', '--out', str(tmp_path)]) == 0
    assert given[-1] == [10, 3]  # in the order given


def test_compare_confirms_on_fresh_seeds_and_refuses_reused_ones(tmp_path, monkeypatch, capsys) -> None:
    given = []

    def compare(scene, plan, seeds, run_done=None, testbed_model='ideal'):
        given.append(list(seeds))
        return stubbed_rows(seeds, run_done)

    monkeypatch.setattr(compare_module, 'compare', compare)
    args = ['robotarium', 'compare', 'robotarium_curve', '--seeds', '0-1', '--out', str(tmp_path)]
    assert main([*args, '--confirm-seeds', '7-8']) == 0
    assert given == [[0, 1, 7, 8]]
    table = (tmp_path / 'compare_robotarium_curve.md').read_text()
    assert '| planned - unplanned, same seeds | verdict |' in table and '4 seeds: **no verdict**' in table  # pooled
    assert main([*args, '--confirm-seeds', '7-8', '--held-out']) == 0
    table = (tmp_path / 'compare_robotarium_curve.md').read_text()
    assert '| planned - unplanned, same seeds | seeds found on | held-out seeds | verdict |' in table
    assert '2 seeds: no verdict' in table  # two seeds of each set: numbers, and no verdict
    given.clear()
    assert main([*args, '--held-out']) == 2 and not given
    assert '--held-out needs seeds to hold out' in capsys.readouterr().err
    assert main([*args, '--confirm-seeds', '1-2']) == 2 and not given
    assert '--confirm-seeds must be fresh seeds: [1] are in --seeds too' in capsys.readouterr().err


def test_compare_with_a_failed_run_exits_1_naming_its_seed_and_mode(tmp_path, monkeypatch, capsys) -> None:
    def compare(scene, plan, seeds, run_done=None, testbed_model='ideal'):
        return stubbed_rows(seeds, run_done, failed=(1, False))

    monkeypatch.setattr(compare_module, 'compare', compare)
    assert main(['robotarium', 'compare', 'robotarium_curve', '--seeds', '2', '--out', str(tmp_path / 'c')]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[-1] == 'FAILED seed 1, unplanned: not every robot parked beyond the exit by the last step'
    rows = json.loads((tmp_path / 'c' / 'compare_robotarium_curve.json').read_text())
    assert [len(row['failures']) for row in rows] == [0, 0, 0, 1]  # the rows are written all the same


def test_the_view_of_a_comparison() -> None:
    view = comparison_view(Comparison('robotarium_curve', (0, 1, 2, 7), '| t |', (Path('a.md'), Path('a.json'))))
    assert view.lines == (
        'scene robotarium_curve, V2 initialization seeds 0-2,7, mean [min, max]:',
        '| t |',
        'written a.md, a.json',
    )
    assert view.exit_code == 0


def test_a_comparison_with_a_failed_run_fails_naming_it() -> None:
    failed = ('seed 2, unplanned: not every robot parked beyond the exit by the last step',)
    view = comparison_view(Comparison('robotarium_curve', (0, 1, 2), '| t |', (Path('a.md'), Path('a.json')), failed))
    assert view.exit_code == 1 and view.lines[-1] == f'FAILED {failed[0]}'


def test_a_scene_off_the_arena_is_refused_before_any_run(tmp_path, capsys) -> None:
    assert main(['robotarium', 'run', 'A', '--out', str(tmp_path)]) == 2
    assert 'does not fit the Robotarium' in capsys.readouterr().err


def test_a_run_without_the_testbeds_initialization_says_its_verdict_is_not_the_testbeds() -> None:
    """Issue 49: a tube flew clean without V2's initialization and failed with it; the run says so."""
    from dataclasses import replace

    from vtube.cli.robotarium import NOT_THE_TESTBEDS_START

    clean = run(VerifierCounts(), None)
    assert not any(line.startswith('  start ') for line in experiment_view(clean).lines)
    shortcut = experiment_view(replace(clean, initialized=False))
    assert f'  start                  {NOT_THE_TESTBEDS_START}' in shortcut.lines
    assert shortcut.data['initialized'] is False and "not from the testbed's start" in NOT_THE_TESTBEDS_START
