"""The speed-constrained simulator, its log, the passage metrics and a reduced form of the paper's study."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest

from vtube_planning import ParamsError, PlanError, SwarmParams, load_scene
from vtube_planning.campaign import Campaign
from vtube_planning.campaign_runner import run_campaign
from vtube_planning.log import read_log
from vtube_planning.planning.planner import plan_convex
from vtube_planning.study import MODES
from vtube_planning.study_report import summarise
from vtube_planning.swarm import simulate as simulate_module
from vtube_planning.swarm.metrics import passage_metrics
from vtube_planning.swarm.simulate import SimConfig, default_constant_speed, simulate

SHORT = SimConfig(time_limit_s=4.0)


@pytest.fixture(scope='module')
def scene_a():
    scene = load_scene('A')
    return scene, plan_convex(scene.tube, scene.swarm, scene.planning, scene='A')


def test_same_seed_same_run_other_seed_other_run(scene_a) -> None:
    scene, plan = scene_a
    one = simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=SHORT)
    two = simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=SHORT)
    other = simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=replace(SHORT, seed=1))
    np.testing.assert_array_equal(one.positions_m, two.positions_m)
    assert not np.array_equal(one.positions_m, other.positions_m)
    assert one.positions_m.shape == (one.t_s.size, 2, 20) and one.r_a_m.shape == (one.t_s.size, 20)


@pytest.mark.parametrize('planned', [True, False])
@pytest.mark.parametrize('limits', [True, False])
def test_every_command_respects_the_speed_band(scene_a, planned: bool, limits: bool) -> None:
    scene, plan = scene_a
    result = simulate(
        scene.tube,
        scene.swarm,
        scene.control,
        plan=plan if planned else None,
        config=replace(SHORT, acceleration_limits=limits),
    )
    speed = np.hypot(result.commands_mps[:, 0], result.commands_mps[:, 1])
    assert speed.min() >= scene.swarm.v_min_mps - 1e-9 and speed.max() <= scene.swarm.v_max_mps + 1e-9
    assert result.metrics.speed_violations == 0
    if not planned:
        assert np.all(result.r_a_m == scene.swarm.r_a_m)  # constant without planning


def test_acceleration_limits_bound_speed_change_and_turn_rate(scene_a) -> None:
    scene, plan = scene_a
    config = replace(SHORT, acceleration_limits=True)
    result = simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=config)
    v = result.velocities_mps
    speed = np.hypot(v[:, 0], v[:, 1])
    assert np.abs(np.diff(speed, axis=0)).max() <= scene.swarm.a_v_mps2 * config.dt_s + 1e-12
    heading = np.unwrap(np.arctan2(v[:, 1], v[:, 0]), axis=0)
    turn_rate = np.abs(np.diff(heading, axis=0)) / config.dt_s
    assert np.all(turn_rate * speed[1:] <= scene.swarm.a_n_mps2 * (1 + 1e-9))
    free = simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=SHORT)
    np.testing.assert_allclose(free.velocities_mps[1:], free.commands_mps[:-1])  # the paper's model: p' = v_c


def test_interrupted_run_leaves_a_readable_log(scene_a, tmp_path, monkeypatch) -> None:
    scene, plan = scene_a
    real = simulate_module.SwarmStep.__call__
    calls = {'n': 0}

    def failing(*args, **kwargs):
        calls['n'] += 1
        if calls['n'] > 57:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(simulate_module.SwarmStep, '__call__', failing)
    log = tmp_path / 'run.npz'
    with pytest.raises(KeyboardInterrupt):
        simulate(
            scene.tube,
            scene.swarm,
            scene.control,
            plan=plan,
            config=replace(SHORT, log_every=10),
            log_path=log,
            meta={'scene': 'A'},
        )
    assert not log.exists()  # unfinished: the rows are in the partial log
    arrays, meta = read_log(tmp_path / 'run.partial.npz')
    assert arrays['positions_m'].shape == (50, 2, 20)  # every row up to the last flush
    assert meta['scene'] == 'A' and meta['planned'] and 'metrics' not in meta
    monkeypatch.setattr(simulate_module.SwarmStep, '__call__', real)
    done = simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=SHORT, log_path=log)
    arrays, meta = read_log(log)
    np.testing.assert_array_equal(arrays['positions_m'], done.positions_m)
    assert meta['finished'] and meta['metrics']['min_distance_m'] == done.metrics.min_distance_m


def test_metrics_of_a_constructed_passage() -> None:
    t = np.arange(0.0, 11.0)
    # two robots along a 10 m tube at 2 m/s, the second 1 m behind, 0.5 m apart laterally from t = 4 to 6
    l = np.stack([2.0 * t - 1.0, 2.0 * t - 2.0], axis=1)
    y = np.zeros_like(l)
    y[4:7, 1] = 0.5
    positions = np.stack([l, y], axis=1)  # (T, 2, N) along the x axis
    positions[4:7, 0, 1] = positions[4:7, 0, 0]  # abreast, 0.5 m apart: closer than 2 r_p = 0.6
    clearance = 1.0 - np.abs(y)
    clearance[3, 0] = -0.2  # robot 0 pokes out once, inside the span (l = 5 m)
    clearance[8, 0] = -0.5  # and once past the exit (l = 15 m), which does not count
    m = passage_metrics(t, positions, l, clearance, 10.0, collision_distance_m=0.6)
    assert m.completed and m.passing_time_s == pytest.approx(6.0 - 1.0)  # enters at t=1 (l=1), last exits t=6
    assert m.min_distance_m == pytest.approx(0.5) and m.min_distance_time_s == 4.0
    assert m.collision_pairs == 1 and m.collision_steps == 3
    assert m.tube_violation_steps == 1 and m.robots_outside == 1 and m.max_outside_m == pytest.approx(0.2)
    assert passage_metrics(t, positions, l, clearance, 10.0, collision_distance_m=0.4).collision_pairs == 0
    commands = np.stack([np.full((11, 2), 2.0), np.zeros((11, 2))], axis=1)  # speed 2 m/s
    assert (
        passage_metrics(
            t, positions, l, clearance, 10.0, collision_distance_m=0.6, speed_band_mps=(2.5, 5.0), commands_mps=commands
        ).speed_violations
        == 22
    )
    assert m.speed_violations is None and m.speed_tracking_mean_mps is None
    # with bodies of radius 0.05 m, clearances below 0.05 m count
    clearance[5, 1] = 0.03  # a body crossing the wall while its centre is inside
    bodies = passage_metrics(t, positions, l, clearance, 10.0, collision_distance_m=0.6, body_radius_m=0.05)
    centres = passage_metrics(t, positions, l, clearance, 10.0, collision_distance_m=0.6)
    assert bodies.tube_violation_steps == centres.tube_violation_steps + 1
    assert bodies.max_outside_m == pytest.approx(0.2 + 0.05)


def test_metrics_json_is_strict() -> None:
    t = np.arange(0.0, 4.0)
    l = np.stack([t, t - 0.5], axis=1)  # a 10 m tube that nobody leaves: no passing time
    positions = np.stack([l, np.zeros_like(l)], axis=1)
    m = passage_metrics(t, positions, l, np.ones_like(l), 10.0, collision_distance_m=0.6)
    assert math.isnan(m.passing_time_s) and not m.completed
    text = json.dumps(m.to_json(), allow_nan=False)  # would raise on NaN
    assert json.loads(text)['passing_time_s'] is None and json.loads(text)['min_distance_m'] == 0.5


def test_bad_simulation_input_is_refused(scene_a) -> None:
    scene, plan = scene_a
    with pytest.raises(ParamsError, match='n_robots must be an integer >= 1'):
        replace(scene.swarm, n_robots=0)
    with pytest.raises(ParamsError, match='needs r_a_m > r_s_m'):
        simulate(scene.tube, replace(scene.swarm, r_a_m=0.4), scene.control, plan=None, config=SHORT)
    other = load_scene('C')
    with pytest.raises(PlanError, match=r"the plan \(made for scene 'A'\) does not fit this run: .*a different tube"):
        simulate(other.tube, other.swarm, other.control, plan=plan, config=SHORT)
    with pytest.raises(PlanError, match=r'other swarm parameters \(v_max_mps\)'):
        simulate(scene.tube, replace(scene.swarm, v_max_mps=4.5), scene.control, plan=plan, config=SHORT)
    robotarium = load_scene('robotarium_trapezoid')
    with pytest.raises(PlanError, match='different tube'):
        simulate(robotarium.tube, robotarium.swarm, robotarium.control, plan=plan, config=SHORT)
    with pytest.raises(ParamsError, match='dt_s must be a finite number > 0'):
        SimConfig(dt_s=0.0)
    with pytest.raises(ParamsError, match='constant_speed_mps = 9.0 lies outside'):
        simulate(scene.tube, scene.swarm, scene.control, plan=None, constant_speed_mps=9.0, config=SHORT)
    assert default_constant_speed(scene.swarm) == 3.5


@pytest.mark.slow
def test_reduced_study_reproduces_the_papers_claim(tmp_path) -> None:
    """The full study (scenes A-D, 5 seeds, flocking on C and D) runs in `vtube study --baselines`; here A and D, seed 0."""
    grids = ({'scene': ('A', 'D'), 'mode': MODES}, {'scene': ('D',), 'mode': ('flocking', 'flocking (v_min)')})
    summary = summarise(run_campaign(Campaign(grids), tmp_path, progress=False).rows)
    assert summary[0]['modes'] == ['planning', 'no planning']  # baselines only on the rapid scenes
    assert summary[1]['modes'] == ['planning', 'no planning', 'flocking', 'flocking (v_min)']
    assert summary[1]['flocking']['collision_pairs'] > 0 and summary[1]['safer_than']['flocking']
    for entry in summary:
        planned, unplanned = entry['planning'], entry['no planning']
        assert planned['completed'] and unplanned['completed']
        assert planned['passing_time_s'] < unplanned['passing_time_s']
        assert planned['min_distance_m'] > unplanned['min_distance_m']
        assert planned['collision_pairs'] == 0 and planned['min_distance_m'] >= 2 * SwarmParams().r_p_m
        assert entry['claim_on_means']


def test_planned_swarm_expands_before_the_narrowing(scene_a) -> None:
    scene, plan = scene_a
    result = simulate(scene.tube, scene.swarm, scene.control, plan=plan)
    center = result.l_m.mean(axis=1)
    before = (center > 5.0) & (center < 20.0)
    assert result.r_a_m[before].mean() > 1.2 * scene.swarm.r_a_m  # (a3) grew r_a
    assert result.density_per_m2[before].min() < plan.density(10.0) * 1.05  # density reached the plan
    assert result.metrics.density_tracking_mean_per_m2 < 0.15


def test_a_run_that_cannot_fit_in_memory_is_refused_before_it_starts(scene_a, monkeypatch) -> None:
    scene, plan = scene_a
    config = SimConfig(time_limit_s=10.0)  # 501 steps of 20 robots: 2 x 501 x 20 x 10 floats = 1.6 MB
    monkeypatch.setattr(simulate_module, 'available_memory_bytes', lambda: 1_500_000)
    with pytest.raises(ParamsError, match=r'flying 20 robots for up to 10 s .* more than the 0.0 GiB available'):
        simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=config)
    monkeypatch.setattr(simulate_module, 'available_memory_bytes', lambda: 1_700_000)
    assert simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=config).t_s.size > 1
