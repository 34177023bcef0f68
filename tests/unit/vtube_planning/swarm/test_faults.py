"""Fault models of the simulator: pose noise, command latency and lag, a failing robot; each off by default and
seeded."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vtube_planning.errors import ParamsError
from vtube_planning.geometry.scene import load_scene
from vtube_planning.planning.planner import plan_convex
from vtube_planning.swarm.faults import RobotFailure
from vtube_planning.swarm.metrics import passage_metrics
from vtube_planning.swarm.simulate import SimConfig, simulate


@pytest.fixture(scope='module')
def scene_a():
    scene = load_scene('A')
    return scene, plan_convex(scene.tube, scene.swarm, scene.planning, scene='A')


def recording_baseline(speed: float = 3.0):
    """A law that drives along the tube at ``speed`` and records what the controller is shown."""
    seen: list[np.ndarray] = []

    def law(positions: np.ndarray, velocities: np.ndarray, projection) -> np.ndarray:
        seen.append(positions.copy())
        return speed * projection.tangent

    return law, seen


def test_pose_noise_is_what_the_controller_sees_with_the_stated_statistics(scene_a) -> None:
    scene, _ = scene_a
    law, seen = recording_baseline()
    config = SimConfig(time_limit_s=4.0, pose_noise_m=0.05)
    result = simulate(scene.tube, scene.swarm, scene.control, plan=None, config=config, baseline=law)
    error = np.array(seen) - result.positions_m  # (T, 2, N): what it saw minus the truth
    assert error.size > 3000
    assert abs(error.mean()) < 0.003 and error.std() == pytest.approx(0.05, rel=0.05)
    assert abs(np.corrcoef(error[:, 0].ravel(), error[:, 1].ravel())[0, 1]) < 0.05  # axes independent
    clean = simulate(scene.tube, scene.swarm, scene.control, plan=None, config=SimConfig(time_limit_s=4.0))
    np.testing.assert_array_equal(result.positions_m[0], clean.positions_m[0])  # the formation's draws unchanged
    again = simulate(scene.tube, scene.swarm, scene.control, plan=None, config=config, baseline=recording_baseline()[0])
    np.testing.assert_array_equal(again.positions_m, result.positions_m)  # seeded


@pytest.mark.parametrize('latency', [1, 3])
def test_commands_arrive_exactly_latency_periods_late(scene_a, latency: int) -> None:
    scene, plan = scene_a
    config = SimConfig(time_limit_s=3.0, latency_steps=latency)
    result = simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=config)
    v, u = result.velocities_mps, result.commands_mps  # v[k]: velocity during step k; u[k]: computed at step k
    for k in range(1, latency + 1):
        np.testing.assert_array_equal(v[k], v[0])  # nothing has arrived yet: the initial velocity
    np.testing.assert_array_equal(v[latency + 1 :], u[: -latency - 1])  # v[k + 1] = u[k - latency]
    prompt = simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=SimConfig(time_limit_s=3.0))
    np.testing.assert_array_equal(prompt.velocities_mps[1:], prompt.commands_mps[:-1])  # latency 0: next step


def test_a_lag_makes_each_period_fly_the_lags_mean_velocity(scene_a) -> None:
    """After the latency, v[k + 1] is the mean over the period of a first-order lag driven by u[k - latency] from
    its state, which ends at u + (state - u) exp(-dt / lag): recomputed here period by period."""
    scene, plan = scene_a
    latency, lag, dt = 2, 0.15, 0.02
    config = SimConfig(time_limit_s=2.0, latency_steps=latency, lag_s=lag, dt_s=dt)
    result = simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=config)
    v, u = result.velocities_mps, result.commands_mps
    state, decay = v[0].copy(), math.exp(-dt / lag)
    for k in range(len(v) - 1):
        arriving = v[0] if k < latency else u[k - latency]
        mean = arriving + (state - arriving) * (lag / dt) * (1.0 - decay)
        np.testing.assert_allclose(v[k + 1], mean, atol=1e-12)
        state = arriving + (state - arriving) * decay
    assert np.abs(v[-1] - u[-1 - latency - 1]).max() > 1e-3  # the lag shows: not the delayed command itself


@pytest.mark.parametrize('mode', ['stop', 'coast'])
def test_a_failed_robot_stops_or_coasts_and_the_others_pass_it(scene_a, mode: str) -> None:
    scene, plan = scene_a
    failure = RobotFailure(robot=0, at_m=8.0, mode=mode)
    result = simulate(
        scene.tube, scene.swarm, scene.control, plan=plan, config=SimConfig(time_limit_s=22.0, failure=failure)
    )  # 22 s: the coasting swarm is out by 18.3 s; the stopped one has settled behind the dead robot
    k = int(np.argmax(result.l_m[:, 0] >= 8.0))  # the first step past the failure point
    after = result.positions_m[k + 1 :, :, 0]
    if mode == 'stop':
        np.testing.assert_array_equal(after, np.broadcast_to(after[0], after.shape))
        assert not result.metrics.completed  # robots held up behind it never leave the tube
    else:
        steps = np.diff(after, axis=0)
        np.testing.assert_allclose(steps, np.broadcast_to(steps[0], steps.shape), atol=1e-12)  # a straight line
    others = np.hypot(*(result.positions_m[:, :, 1:] - result.positions_m[:, :, :1]).transpose(1, 0, 2))
    assert others.min() > 2 * scene.swarm.r_p_m  # the others avoid it
    out = result.l_m[-1, 1:] > scene.tube.length_m
    m = result.metrics  # the failed robot counts for distances, not for the passage
    assert (m.robots_counted, m.robots_passed) == (19, out.sum()) and m.completed == out.all()
    if mode == 'coast':
        assert out.all() and np.isfinite(m.passing_time_s)  # every other robot passes it and leaves the tube
    else:  # those still inside are held up right behind the dead robot
        held = result.positions_m[-1, :, 1:][:, ~out] - result.positions_m[-1, :, :1]
        assert out.sum() >= 15 and np.all(np.hypot(*held) < 2 * (scene.swarm.r_s_m + 3 * scene.swarm.r_a_m))


def test_bad_fault_settings_are_refused(scene_a) -> None:
    scene, plan = scene_a
    with pytest.raises(ParamsError, match='pose_noise_m must be a finite number >= 0'):
        SimConfig(pose_noise_m=-0.1)
    with pytest.raises(ParamsError, match='latency_steps must be a whole number >= 0'):
        SimConfig(latency_steps=True)
    with pytest.raises(ParamsError, match='lag_s must be a finite number >= 0'):
        SimConfig(lag_s=-0.1)
    with pytest.raises(ParamsError, match="failure mode must be one of \\('stop', 'coast'\\)"):
        RobotFailure(robot=0, at_m=1.0, mode='explode')
    with pytest.raises(ParamsError, match='robots 0..19'):
        simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=SimConfig(failure=RobotFailure(20, 1.0)))


def test_avoidance_of_what_is_heard_equals_the_pairwise_law_when_everything_arrives() -> None:
    from vtube_planning.onboard.law import avoidance_velocity
    from vtube_planning.params import ControlParams

    scene = load_scene('A')
    rng = np.random.default_rng(3)
    positions = np.vstack([rng.uniform(0, 12, 60), rng.uniform(-3, 3, 60)])
    r_a = rng.uniform(0.8, 2.0, 60)
    members = rng.random(60) > 0.2
    for law in ('barrier', 'practical'):
        params = ControlParams(law=law).step_params(scene.swarm)
        pairwise = avoidance_velocity(positions, r_a, params, members)
        heard = avoidance_velocity(positions, r_a, params, members, others=positions.copy())
        assert np.abs(pairwise).max() > 0.1
        np.testing.assert_allclose(heard, pairwise, rtol=1e-10, atol=1e-12)


def test_dropped_messages_leave_the_stated_share_of_robots_heard_where_they_were(scene_a, monkeypatch) -> None:
    import vtube_planning.onboard.stepper as step_module

    scene, plan = scene_a
    views: list[tuple[np.ndarray, np.ndarray]] = []
    original = step_module.SwarmStep.__call__

    def recording(self, points, dt_s, projection=None, others=None):
        views.append((points.copy(), others.copy()))
        return original(self, points, dt_s, projection, others)

    monkeypatch.setattr(step_module.SwarmStep, '__call__', recording)
    simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=SimConfig(time_limit_s=4.0, dropout=0.3))
    stale = np.array([np.any(others != points, axis=0) for points, others in views[1:]])  # (T, N): heard elsewhere
    assert stale.mean() == pytest.approx(0.3, abs=0.02)  # stale exactly while its last message was lost
    for (points, others), (_, heard_before) in zip(views[1:], views[:-1], strict=True):
        lost = np.any(others != points, axis=0)
        np.testing.assert_array_equal(others[:, lost], heard_before[:, lost])  # the last message heard, unchanged
    with pytest.raises(ParamsError, match='dropout must be a probability in \\[0, 1\\)'):
        SimConfig(dropout=1.0)


def test_a_robot_left_out_of_the_count_does_not_hold_up_the_passage() -> None:
    """Two robots on a 10 m tube at 1 m/s, one 2 m behind the other; the second stops at l = 5 m."""
    t = np.arange(0.0, 20.0, 0.5)
    l_m = np.column_stack([t - 1.0, np.minimum(t - 3.0, 5.0)])
    positions = np.stack([l_m, np.zeros_like(l_m)], axis=1)  # along the x axis: (T, 2, N)
    clearance = np.ones_like(l_m)
    everyone = passage_metrics(t, positions, l_m, clearance, 10.0, collision_distance_m=0.1)
    assert not everyone.completed and math.isnan(everyone.passing_time_s) and everyone.robots_passed == 1
    first = passage_metrics(
        t, positions, l_m, clearance, 10.0, collision_distance_m=0.1, counted=np.array([True, False])
    )
    assert first.completed and first.passing_time_s == pytest.approx(10.0)  # enters at 1 s, exits at 11 s
    assert (first.robots_passed, first.robots_counted) == (1, 1)
    assert first.min_distance_m == everyone.min_distance_m  # distances count every robot
