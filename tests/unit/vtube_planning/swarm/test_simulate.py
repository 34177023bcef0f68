"""The speed-constrained simulator: seeded, within the speed band and the acceleration limits, interrupted runs
leave a readable log, bad input refused before the run."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import vtube_planning.swarm.simulate as simulate_module
from robotarium_exp.scene import load_scene
from vtube_planning.errors import ParamsError, PlanError, ShapeError
from vtube_planning.log import read_log
from vtube_planning.planning.planner import plan_convex
from vtube_planning.swarm.simulate import SimConfig, default_constant_speed, simulate

SHORT = SimConfig(time_limit_s=4.0)


@pytest.fixture(scope='module')
def scene_a():
    scene = load_scene('A')
    return scene, plan_convex(scene.tube, scene.swarm, scene.planning, scene='A')


@pytest.fixture(scope='module')
def short_flight(scene_a):
    """The 4 s flight of scene A, with or without the plan and the acceleration limits, each flown once."""
    scene, plan = scene_a
    flown = {}

    def fly(planned: bool = True, limits: bool = False):
        if (planned, limits) not in flown:
            config = replace(SHORT, acceleration_limits=limits)
            flown[planned, limits] = simulate(
                scene.tube, scene.swarm, scene.control, plan=plan if planned else None, config=config
            )
        return flown[planned, limits]

    return fly


def test_same_seed_same_run_other_seed_other_run(scene_a, short_flight) -> None:
    scene, plan = scene_a
    one = short_flight()
    two = simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=SHORT)
    other = simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=replace(SHORT, seed=1))
    np.testing.assert_array_equal(one.positions_m, two.positions_m)
    assert not np.array_equal(one.positions_m, other.positions_m)
    assert one.positions_m.shape == (one.t_s.size, 2, 20) and one.r_a_m.shape == (one.t_s.size, 20)


@pytest.mark.parametrize('planned', [True, False])
@pytest.mark.parametrize('limits', [True, False])
def test_every_command_respects_the_speed_band(scene_a, short_flight, planned: bool, limits: bool) -> None:
    scene, _ = scene_a
    result = short_flight(planned, limits)
    speed = np.hypot(result.commands_mps[:, 0], result.commands_mps[:, 1])
    assert speed.min() >= scene.swarm.v_min_mps - 1e-9 and speed.max() <= scene.swarm.v_max_mps + 1e-9
    assert result.metrics.speed_violations == 0
    if not planned:
        assert np.all(result.r_a_m == scene.swarm.r_a_m)  # constant without planning


def test_acceleration_limits_bound_speed_change_and_turn_rate(scene_a, short_flight) -> None:
    scene, _ = scene_a
    config = replace(SHORT, acceleration_limits=True)
    result = short_flight(True, True)
    v = result.velocities_mps
    speed = np.hypot(v[:, 0], v[:, 1])
    assert np.abs(np.diff(speed, axis=0)).max() <= scene.swarm.a_v_mps2 * config.dt_s + 1e-12
    heading = np.unwrap(np.arctan2(v[:, 1], v[:, 0]), axis=0)
    turn_rate = np.abs(np.diff(heading, axis=0)) / config.dt_s
    assert np.all(turn_rate * speed[1:] <= scene.swarm.a_n_mps2 * (1 + 1e-9))
    free = short_flight()
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


def test_planned_swarm_expands_before_the_narrowing(scene_a) -> None:
    scene, plan = scene_a
    result = simulate(scene.tube, scene.swarm, scene.control, plan=plan)
    center = result.l_m.mean(axis=1)
    before = (center > 5.0) & (center < 20.0)
    assert result.r_a_m[before].mean() > 1.2 * scene.swarm.r_a_m  # (a3) grew r_a
    assert result.density_per_m2[before].min() < plan.density(10.0) * 1.05  # density reached the plan
    assert result.metrics.density_tracking_mean_per_m2 < 0.15


def test_a_flight_starts_from_the_given_positions_and_its_log_says_so(scene_a) -> None:
    """Given positions are the first logged step as given, moving along the tube at v_min (no plan); the config keeps
    them as comparable, hashable rows; a count other than the swarm's is refused before the run."""
    scene, _ = scene_a
    tube, swarm = scene.tube, replace(scene.swarm, n_robots=3)
    given = np.stack(
        [tube.center_at(l_m) + y_m * tube.normal(l_m) for l_m, y_m in [(1.0, 1.0), (1.0, -1.0), (-2.0, 0)]]
    )
    config = SimConfig(time_limit_s=0.1, initial_positions_m=given.T)
    assert config == SimConfig(time_limit_s=0.1, initial_positions_m=given.T.tolist()) and hash(config) == hash(config)
    flown = simulate(tube, swarm, scene.control, plan=None, config=config)
    np.testing.assert_array_equal(flown.positions_m[0], given.T)
    np.testing.assert_allclose(flown.velocities_mps[0], swarm.v_min_mps * tube.project(given.T).tangent, atol=1e-12)
    assert flown.meta['start'] == 'given positions'
    assert (
        'start'
        not in simulate(tube, swarm, scene.control, plan=None, config=replace(config, initial_positions_m=None)).meta
    )
    with pytest.raises(ParamsError, match='3 initial positions were given for a swarm of 2 robots'):
        simulate(tube, replace(swarm, n_robots=2), scene.control, plan=None, config=config)
    with pytest.raises(ShapeError, match=r'initial_positions_m must have shape \(2, N\)'):
        SimConfig(initial_positions_m=given)
