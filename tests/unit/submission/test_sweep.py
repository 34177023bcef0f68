"""The sweep's row logic on runs constructed here (a whole case runs in ``tests/integration/test_sweep.py``): each
run's measures against independent recomputations, each criterion of the bar, the store and the table."""

from __future__ import annotations

import csv
import hashlib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import submission.sweep as sweep_module
from robotarium_exp.experiment import ExperimentConfig, flight_data
from robotarium_exp.fit import Fit, Misfit
from robotarium_exp.flight_data import FlightData
from robotarium_exp.scene import load_scene
from robotarium_exp.spec import ROBOTARIUM
from submission.check import RunReport
from submission.errors import SubmissionError
from submission.recording import SimulatorRecord
from submission.sweep import (
    DIP_ERROR_BAR,
    Case,
    RunMeasures,
    case_key,
    case_row,
    flown_scene,
    judge,
    measure_run,
    parked_at_end,
    summarise,
    sweep,
    sweep_markdown,
)
from vtube_planning.errors import SolverError
from vtube_planning.geometry.from_maps.map_file import generated_scene
from vtube_planning.geometry.scene import Scene
from vtube_planning.planning.plan import Plan
from vtube_planning.planning.planner import plan_convex

STEPS, DT = 400, 0.033
LANE_M = 0.1


@pytest.fixture(scope='module')
def planned() -> tuple[Scene, Plan, FlightData]:
    """The trapezoid with two robots looking 0.5 m ahead (a plan with a dip), its plan and its flight data."""
    scene = load_scene('robotarium_trapezoid', n_robots=2)
    scene = replace(scene, planning=replace(scene.planning, lookahead_m=0.5))
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    return scene, plan, flight_data(scene, plan, ExperimentConfig())


def marching(scene: Scene, data: FlightData, *, wall_steps: range = range(0)) -> SimulatorRecord:
    """Two robots abreast (y = +-LANE_M) walking the straight tube from l = -0.1 to L + 0.2 at constant speed, then
    standing with their control points on their slots; robot 1 drives with its body on the wall in ``wall_steps``."""
    length = scene.tube.length_m
    x0 = float(scene.tube.center_at(0.0)[0])
    poses = np.zeros((STEPS, 3, 2))
    poses[:, 0, :] = (x0 + np.linspace(-0.1, length + 0.2, STEPS))[:, None]
    poses[:, 1, :] = [-LANE_M, LANE_M]
    for k in wall_steps:
        l_k = poses[k, 0, 1] - x0
        poses[k, 1, 1] = float(scene.tube.half_width(l_k)) - 0.5 * ROBOTARIUM.robot_diameter_m + 0.01
    poses[-1, :2] = data.parking_slots - np.array([[data.projection_distance_m], [0.0]])
    commands = np.zeros((STEPS, 2, 2))
    commands[:, 0] = 0.1
    commands[-1] = 0.0
    return SimulatorRecord(poses, commands, DT, {}, STEPS + 10, 10, 1, True)


def test_a_clean_march_measures_as_recomputed_here(planned) -> None:
    scene, plan, data = planned
    run = RunReport('bundled', 0, 0, record=marching(scene, data), completed=True)
    measured = measure_run(run, data, scene, plan)
    length = scene.tube.length_m
    l_c = np.linspace(-0.1, length + 0.2, STEPS)[:-1]  # the march (its last pose is replaced by the slot)
    assert measured.problems == ()
    assert (measured.too_close, measured.outside, measured.actuator) == (0, 0, 0)
    assert measured.through and measured.parked
    assert measured.body_on_wall == 0
    # first recorded step at or past the exit, less the first at or past the entrance
    assert measured.passing_time_s == pytest.approx(DT * (np.argmax(l_c >= length) - np.argmax(l_c >= 0.0)))
    assert measured.min_distance_m == pytest.approx(2 * LANE_M)
    # the dip error recomputed from the tube's area: both robots at the centre's l, padded by the initial r_a
    active = plan.l_m[plan.active['p7']]
    in_dip = (l_c >= active.min()) & (l_c <= active.max())
    r_a = scene.swarm.r_a_m
    rho = 2 / (np.asarray(scene.tube.area(l_c + r_a)) - np.asarray(scene.tube.area(l_c - r_a)))
    expected = np.mean(np.abs(rho - plan.density(l_c))[in_dip] / plan.density(l_c)[in_dip])
    assert in_dip.sum() > 10
    assert measured.dip_error == pytest.approx(expected, rel=1e-9)


def test_body_on_the_wall_counts_the_robot_steps_inside_the_tube(planned) -> None:
    scene, plan, data = planned
    run = RunReport('bundled', 0, 0, record=marching(scene, data, wall_steps=range(100, 107)), completed=True)
    measured = measure_run(run, data, scene, plan)
    assert measured.body_on_wall == 7
    assert judge([measured])[0] == 'FAIL'


def test_parked_needs_every_control_point_in_its_own_slot(planned) -> None:
    _, _, data = planned
    d, slots = data.projection_distance_m, data.parking_slots
    pose = np.vstack([slots - np.array([[d], [0.0]]), np.zeros(2)])
    still = np.zeros((2, 2))
    assert parked_at_end(pose, still, DT, data)
    off = pose.copy()
    off[1, 0] += 0.04  # beyond the flight's 0.03 m
    assert not parked_at_end(off, still, DT, data)
    same = pose.copy()
    same[:2, 1] = same[:2, 0] + 0.005  # both robots at slot 0
    assert not parked_at_end(same, still, DT, data)
    # the last recorded step still moves the robot: 0.6 m/s for one step closes a 0.02 m gap, -0.6 m/s does not
    behind = pose.copy()
    behind[0] -= 0.02
    assert parked_at_end(behind, np.array([[0.6, 0.6], [0.0, 0.0]]), DT, data)
    assert not parked_at_end(behind, np.array([[-0.6, -0.6], [0.0, 0.0]]), DT, data)


def test_a_run_without_record_is_measured_as_its_preflight_problem(planned) -> None:
    scene, plan, data = planned
    measured = measure_run(RunReport('bundled', 2, -1, timed_out_s=5.0), data, scene, plan)
    assert not measured.through and not measured.parked
    assert judge([measured]) == ('FAIL', 'bundled seed 2: did not finish in 5 s (raise --run-timeout if it should)')


def test_verifier_counts_take_the_worse_of_the_simulator_and_the_recount(planned) -> None:
    scene, plan, data = planned
    rec = marching(scene, data)
    close = rec.poses.copy()
    close[50:53, 1, 1] = close[50:53, 1, 0] + 0.05  # three steps 0.05 m apart: the recount says too close
    errors = {'robots_too_close': 1, 'exceeded_actuator_limits': 4}
    run = RunReport(
        'bundled',
        0,
        0,
        record=SimulatorRecord(close, rec.commands, DT, errors, STEPS + 10, 10, 1, True),
        completed=True,
    )
    measured = measure_run(run, data, scene, plan)
    assert (measured.too_close, measured.actuator) == (3, 4)
    status, reason = judge([measured])
    assert status == 'FAIL'
    assert 'the testbed would not run it (1 pair-steps of robots too close' in reason


WALL = 'robot bodies were on the tube walls in {} robot-steps (1 robots, up to 0.010 m over)'
"""The preflight's problem of a run with bodies on a wall (`robotarium_exp.verifier.wall_failure`)."""


def good(label: str = 'bundled seed 0', **change) -> RunMeasures:
    values = {'problems': (), 'too_close': 0, 'outside': 0, 'actuator': 0, 'through': True, 'parked': True}
    values['dip_error'] = 0.1
    return RunMeasures(label, **(values | change))


@pytest.mark.parametrize(
    ('bad', 'named'),
    [
        (good(parked=False), 'not every robot parked in its slot'),
        (good(body_on_wall=3, problems=(WALL.format(3),)), 'robot bodies were on the tube walls in 3 robot-steps'),
        (good(dip_error=DIP_ERROR_BAR + 0.01), 'density error in the dip 26 % > 25 %'),
        (good(problems=("not every robot ended past the tube's exit (the flight did not complete)",)), 'exit'),
    ],
)
def test_each_criterion_fails_the_case_by_name(bad: RunMeasures, named: str) -> None:
    status, reason = judge([good(), bad])
    assert status == 'FAIL'
    assert reason.startswith('bundled seed 0: ')
    assert named in reason


def test_a_case_passes_at_the_bar_without_a_dip_and_not_without_runs() -> None:
    assert judge([good(dip_error=DIP_ERROR_BAR), good(dip_error=None)]) == ('PASS', '')
    assert judge([])[0] == 'FAIL'


def test_a_criterion_failed_by_several_seeds_is_named_once_with_the_first() -> None:
    walls = [good('seed 0', body_on_wall=2, problems=(WALL.format(2),))]
    _, reason = judge([*walls, good('seed 1', body_on_wall=5, parked=False, problems=(WALL.format(5),))])
    assert reason == f'seed 0: {WALL.format(2)}; seed 1: not every robot parked in its slot'


def test_summary_sums_counts_and_keeps_the_worst() -> None:
    runs = [good(too_close=1, dip_error=0.2, passing_time_s=30.0, min_distance_m=0.3), good(dip_error=0.1)]
    row = summarise(runs)
    assert (row['too_close'], row['dip_error'], row['min_distance_m']) == (1, 0.2, 0.3)
    assert row['passing_time_s'] == ''  # not every run passed: no passing time for the case


def test_the_key_follows_the_scene_file_and_the_case(tmp_path: Path) -> None:
    scene = tmp_path / 'a.toml'
    scene.write_text('x = 1\n', encoding='utf-8')
    key = case_key(Case(str(scene), 4, (0, 1, 2), tmp_path))
    assert key == case_key(Case(str(scene), 4, (0, 1, 2), tmp_path / 'elsewhere'))
    assert key not in {
        case_key(Case(str(scene), 5, (0, 1, 2), tmp_path)),
        case_key(Case(str(scene), 4, (0, 1), tmp_path)),
    }
    scene.write_text('x = 2\n', encoding='utf-8')
    assert key != case_key(Case(str(scene), 4, (0, 1, 2), tmp_path))


def test_rows_are_stored_as_they_come_and_a_rerun_skips_them(tmp_path: Path, monkeypatch) -> None:
    calls: list[tuple[str, int]] = []

    def row(case: Case) -> dict:
        calls.append((case.scene, case.n_robots))
        if case.n_robots == 2:
            return {'status': 'refused', 'reason': 'too many robots for the entrance; use 1'}
        if case.scene == 'b':
            raise RuntimeError('boom')
        return {'status': 'PASS', 'reason': '', 'through': True, 'dip_error': 0.125}

    monkeypatch.setattr(sweep_module, 'case_row', row)
    outcome = sweep(['a', 'b'], [1, 2], tmp_path, seeds=1)
    assert [r['status'] for r in outcome.rows] == ['PASS', 'refused', 'error', 'refused']
    assert [r['scene'] for r in outcome.failed] == ['b']
    with (tmp_path / 'runs.csv').open(newline='', encoding='utf-8') as handle:
        assert len(list(csv.DictReader(handle))) == 4
    again = sweep(['a', 'b'], [1, 2], tmp_path, seeds=1)
    assert (again.skipped, again.ran) == (3, 1)  # the case that raised is done again
    assert calls[4:] == [('b', 1)]
    text = (tmp_path / 'sweep.md').read_text(encoding='utf-8')
    assert '| a | PASS | refused [1] |' in text
    assert '| b | error [2] | refused [3] |' in text
    assert '2. b, N = 1: RuntimeError: boom' in text
    assert '12.5 %' in text


def test_another_sweep_in_the_same_folder_is_refused(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setattr(sweep_module, 'case_row', lambda case: {'status': 'PASS', 'reason': ''})
    sweep(['a'], [1], tmp_path, seeds=1)
    with pytest.raises(Exception, match='holds the results of another sweep'):
        sweep(['a'], [1], tmp_path, seeds=2)
    sweep(['a'], [1], tmp_path, seeds=(0,))  # seed 0 is the count 1: the same sweep
    with pytest.raises(Exception, match='holds the results of another sweep'):
        sweep(['a'], [1], tmp_path, seeds=(1,))


def test_a_sweep_flies_the_seeds_asked_and_keys_counts_as_before(tmp_path: Path, monkeypatch) -> None:
    flown = []
    monkeypatch.setattr(sweep_module, 'case_row', lambda case: flown.append(case.seeds) or {'status': 'PASS'})
    sweep(['a'], [1], tmp_path / 'ranged', seeds=(10, 11))
    sweep(['a'], [1], tmp_path / 'counted', seeds=2)
    assert flown == [(10, 11), (0, 1)]
    keyed = hashlib.sha256(b'a\n1\n2').hexdigest()[:16]  # the key a count of 2 had before ranges were taken
    assert case_key(Case('a', 1, (0, 1), tmp_path)) == keyed != case_key(Case('a', 1, (10, 11), tmp_path))


def test_the_table_puts_scenes_in_rows_and_n_in_columns() -> None:
    rows = [
        {'scene': 's', 'n_robots': n, 'status': 'PASS', 'reason': '', 'error': '', 'wall_s': 1.0}
        | dict.fromkeys(sweep_module.MEASURES, '')
        for n in (1, 6)
    ]
    text = sweep_markdown(rows, (0, 1, 2))
    assert '| scene | N = 1 | N = 6 |' in text
    assert '| s | PASS | PASS |' in text
    assert 'seeds 0-2. PASS' in text and 'seeds 10-11,4. PASS' in sweep_markdown(rows, (10, 11, 4))


def test_a_case_the_verdict_refuses_is_a_refusal_with_its_reason_and_nothing_is_planned(tmp_path, monkeypatch) -> None:
    misfit = Misfit('the formation leaves the box', 'use N <= 8')
    proved: list[bool] = []
    monkeypatch.setattr(sweep_module, 'robotarium_fit', lambda scene, prove: proved.append(prove) or Fit((misfit,)))
    monkeypatch.setattr(sweep_module, 'plan_convex', lambda *a, **k: pytest.fail('planned a refused case'))
    row = case_row(Case('robotarium_trapezoid', 20, (0,), tmp_path))
    assert proved == [True]  # the sweep asks the verdict to try the proof a refusal may need
    assert row == {'status': 'refused', 'reason': Fit((misfit,)).reason}


def test_a_plan_that_fails_or_is_not_certified_fails_the_case_before_any_build(planned, tmp_path, monkeypatch) -> None:
    _, plan, _ = planned
    monkeypatch.setattr(sweep_module, 'build', lambda *a, **k: pytest.fail('built without a certified plan'))
    uncertified = replace(plan, certificate=dict(plan.certificate) | {'p7': 0.02})
    monkeypatch.setattr(sweep_module, 'plan_convex', lambda *a, **k: uncertified)
    assert case_row(Case('robotarium_trapezoid', 2, (0,), tmp_path)) == {
        'status': 'FAIL',
        'reason': 'plan not certified (worst violation 0.02)',
    }

    def infeasible(*args, **kwargs):
        raise SolverError('no feasible plan; widen the tube')

    monkeypatch.setattr(sweep_module, 'plan_convex', infeasible)
    row = case_row(Case('robotarium_trapezoid', 2, (0,), tmp_path))
    assert row == {'status': 'FAIL', 'reason': 'no plan: no feasible plan; widen the tube'}


def test_a_build_refusal_after_a_fit_is_a_failure_naming_both(planned, tmp_path, monkeypatch) -> None:
    _, plan, _ = planned

    def refuse(*args, **kwargs):
        raise SubmissionError('parking slots leave the arena; move the exit')

    monkeypatch.setattr(sweep_module, 'plan_convex', lambda *a, **k: plan)
    monkeypatch.setattr(sweep_module, 'build', refuse)
    row = case_row(Case('robotarium_trapezoid', 2, (0,), tmp_path))
    assert row['status'] == 'FAIL'
    assert (
        row['reason'] == 'the verdict said it fits, but the build refused: parking slots leave the arena; move the exit'
    )


def test_a_map_file_is_flown_in_the_tube_it_generates_kept_beside_the_rows(tmp_path: Path) -> None:
    """Issue 50's map layouts: a map file in the sweep is generated into ``out/tubes`` under its own name, exactly as
    `generated_scene` writes it, and its cases are that scene's (their keys follow its text); a refusal costs no
    flight. Oracle: the generator called here, and the key of the generated scene's case."""
    from vtube.cli.tube import map_examples

    text = map_examples()['robotarium_gate']
    path = tmp_path / 'gate.toml'
    path.write_text(text, encoding='utf-8')
    out = tmp_path / 'sweep'
    outcome = sweep([str(path)], [21], out, seeds=1)
    generated = out / 'tubes' / 'gate.toml'
    assert generated.read_text(encoding='utf-8') == generated_scene(text, str(path), generated.parent)[0]
    (row,) = outcome.rows
    assert (row['scene'], row['status']) == ('gate', 'refused') and row['reason'].startswith('does not fit')
    assert row['key'] == case_key(Case(str(generated), 21, (0,), out / 'files'))
    assert flown_scene('robotarium_curve', out) == 'robotarium_curve'  # a shipped name is flown as it is,
    assert flown_scene(str(generated), out) == str(generated)  # and so is a scene file (no [tube.generate] left)
