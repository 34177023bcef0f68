"""The testbed model: ideal is the plain simulator, and each effect (delay, lag, gains, noise) against its oracle."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from robotarium_exp.rps.robotarium import Robotarium
from robotarium_exp.rps.testbed_model import (
    FITTED,
    IDEAL,
    Testbed,
    TestbedModel,
    TestbedModelError,
)
from robotarium_exp.rps.testbed_model import testbed_model as named_model

DT = Robotarium.TIME_STEP
START = np.array([[-0.5, 0.0, 0.5], [0.0, 0.3, -0.3], [0.0, 1.0, -2.0]])


def commands(steps: int, n: int = 3, seed: int = 7) -> np.ndarray:
    """Random commands within the wheel limits (steps, 2, n)."""
    rng = np.random.default_rng(seed)
    return np.stack([rng.uniform(-0.1, 0.1, (steps, n)), rng.uniform(-1.0, 1.0, (steps, n))], axis=1)


def fly(model: str | TestbedModel | None, u: np.ndarray, seed: int = 0) -> tuple[np.ndarray, np.ndarray, Robotarium]:
    """Poses handed out (steps + 1, 3, n) and true poses after each step, flying ``u`` from ``START``."""
    np.random.seed(seed)
    extra = {} if model is None else {'testbed_model': model}
    r = Robotarium(
        number_of_robots=u.shape[2],
        show_figure=False,
        sim_in_real_time=False,
        initial_conditions=START[:, : u.shape[2]],
        skip_initialization=True,
        **extra,
    )
    seen, true = [r.get_poses()], [r._poses.copy()]
    for step in u:
        r.set_velocities(np.arange(u.shape[2]), step)
        r.step()
        seen.append(r.get_poses())
        true.append(r._poses.copy())
    return np.array(seen), np.array(true), r


def only_command_path(**changes: float) -> TestbedModel:
    """A model with the given command-path numbers and nothing else (gains exactly 1 unless given)."""
    return replace(IDEAL, name='test', **changes)


def test_ideal_is_the_plain_simulator_bit_for_bit_without_a_draw() -> None:
    u = commands(60)
    plain_seen, plain_true, plain = fly(None, u)
    after_plain = np.random.rand()
    for model in ('ideal', IDEAL, ' ideal '):
        seen, true, r = fly(model, u)
        np.testing.assert_array_equal(seen, plain_seen)
        np.testing.assert_array_equal(true, plain_true)
        np.testing.assert_array_equal(r.get_encoders(), plain.get_encoders())
        assert np.random.rand() == after_plain  # the same number of np.random draws
        assert r._testbed is None


@pytest.mark.parametrize('k', [1, 3, 5])
def test_a_pure_delay_of_k_iterations_shifts_the_motion_by_k_steps(k: int) -> None:
    u = commands(40)
    _, ideal, _ = fly('ideal', u)
    _, delayed, _ = fly(only_command_path(delay_v_steps=k, delay_omega_steps=k), u)
    np.testing.assert_array_equal(delayed[: k + 1], np.repeat(ideal[:1], k + 1, axis=0))  # standing still k steps
    np.testing.assert_array_equal(delayed[k:], ideal[: len(ideal) - k])  # the same arithmetic, k steps later


def test_the_channels_have_their_own_delays_and_a_half_iteration_interpolates() -> None:
    testbed = Testbed(only_command_path(delay_v_steps=1.5, delay_omega_steps=0.0), 1, DT)
    out = [testbed.actuate(np.array([[1.0], [1.0]]))[:, 0] for _ in range(4)]
    np.testing.assert_array_equal(np.array(out), [[0.0, 1.0], [0.5, 1.0], [1.0, 1.0], [1.0, 1.0]])


def test_the_lag_step_response_is_one_minus_exp_of_minus_t_over_tau() -> None:
    tau = 0.19
    testbed = Testbed(only_command_path(lag_s=tau), 2, DT)
    response = np.array([testbed.actuate(np.ones((2, 2)))[0, 0] for _ in range(30)])
    t = DT * np.arange(1, 31)
    np.testing.assert_allclose(response, 1 - np.exp(-t / tau), rtol=1e-12)


def test_gains_and_bias_scale_the_integrated_motion_as_by_hand() -> None:
    model = only_command_path(speed_gain=1.1, turn_gain=0.9, turn_bias_rad_s=0.05)
    u = np.tile(np.array([[0.1], [0.5]]), (25, 1, 1))
    _, true, _ = fly(model, u)
    x, y, theta = START[:, 0]
    for _ in range(25):  # forward Euler at DT with the scaled command, by hand
        x, y = x + DT * 0.11 * math.cos(theta), y + DT * 0.11 * math.sin(theta)
        theta += DT * (0.9 * 0.5 + 0.05)
    np.testing.assert_allclose(true[-1][:, 0], [x, y, theta], atol=1e-12)
    _, standing, _ = fly(model, np.zeros((25, 2, 1)))
    np.testing.assert_array_equal(standing[-1], standing[0])  # no command acting: the bias does not turn it


def test_per_robot_gains_are_drawn_seeded_with_the_models_spread() -> None:
    np.random.seed(3)
    first = Testbed(FITTED, 2000, DT)
    np.random.seed(3)
    assert np.array_equal(Testbed(FITTED, 2000, DT).gains, first.gains)
    for row, (mean, sd) in enumerate(
        [(FITTED.speed_gain, FITTED.speed_gain_sd), (FITTED.turn_gain, FITTED.turn_gain_sd)]
    ):
        assert abs(first.gains[row].mean() - mean) < 4 * sd / math.sqrt(2000)
        assert abs(first.gains[row].std() / sd - 1) < 0.1
    assert abs(first.bias.mean() - FITTED.turn_bias_rad_s) < 4 * FITTED.turn_bias_sd_rad_s / math.sqrt(2000)


def test_pose_noise_has_the_models_spread_along_and_across_the_heading() -> None:
    model = only_command_path(noise_along_m=0.002, noise_across_m=0.001, noise_heading_rad=0.01)
    np.random.seed(5)
    n, draws = 50, 200
    poses = np.vstack([np.zeros((2, n)), np.random.uniform(-3, 3, n)])
    testbed = Testbed(model, n, DT)
    seen = np.array([testbed.observe(poses) for _ in range(draws)])
    d = seen - poses
    c, s = np.cos(poses[2]), np.sin(poses[2])
    along, across = d[:, 0] * c + d[:, 1] * s, -d[:, 0] * s + d[:, 1] * c
    tolerance = 4 / math.sqrt(2 * n * draws)  # 4 standard errors of a sample sd, relative
    for sample, sd in ((along, 0.002), (across, 0.001), (np.angle(np.exp(1j * d[:, 2])), 0.01)):
        assert abs(sample.std() / sd - 1) < tolerance
        assert abs(sample.mean()) < 4 * sd / math.sqrt(n * draws)


def test_headings_come_in_quanta_and_stale_poses_at_their_rates_driving_and_standing() -> None:
    model = only_command_path(heading_quantum_rad=0.001, stale_rate=0.05, stale_rate_still=0.6)
    np.random.seed(11)
    n, draws = 100, 300
    testbed = Testbed(model, n, DT)
    still = np.arange(n) < n // 2
    testbed.actuate(np.where(still, 0.0, 0.1) * np.ones((2, n)))  # the other half drives
    assert np.array_equal(testbed.still(), still)
    previous = None
    repeats = np.zeros(n)
    for k in range(draws):
        poses = np.vstack([np.full(n, 0.001 * k), np.zeros(n), np.random.uniform(-3, 3, n)])
        seen = testbed.observe(poses)
        np.testing.assert_allclose(seen[2] * 1000, np.round(seen[2] * 1000), atol=1e-9)
        if previous is not None:
            repeats += np.all(seen == previous, axis=0)
        fresh = ~np.all(seen == previous, axis=0) if previous is not None else np.ones(n, dtype=bool)
        np.testing.assert_allclose(seen[:2, fresh], poses[:2, fresh], atol=1e-12)  # no outlier: fresh is true
        previous = seen
    for rate, share in ((0.6, repeats[still].mean() / (draws - 1)), (0.05, repeats[~still].mean() / (draws - 1))):
        assert abs(share - rate) < 4 * math.sqrt(rate * (1 - rate) / (n / 2 * (draws - 1)))


def test_a_stalled_robot_drives_on_along_its_arc_at_the_stall_rate() -> None:
    """In a stalled iteration a robot moves (1 + stall_steps) periods' worth of what acts on it, so the pose after
    it lies ahead along the heading (as the real robots' jumps do), and stalls come at their rate."""
    u = np.tile(np.array([[0.1, 0.05], [0.0, 0.5]]), (1, 1, 1))
    always = Testbed(only_command_path(stall_rate=1.0, stall_steps=2.5), 2, DT)
    np.testing.assert_allclose(always.actuate(u[0]), 3.5 * u[0], rtol=1e-12)
    _, true, _ = fly(only_command_path(stall_rate=1.0, stall_steps=2.5), np.repeat(u, 1, axis=0))
    step = true[1, :2, 0] - true[0, :2, 0]  # robot 0 drives straight along its heading (0 rad) ...
    np.testing.assert_allclose(step, [3.5 * DT * 0.1, 0.0], atol=1e-12)  # ... 3.5 periods' worth
    np.random.seed(4)
    n, draws = 10, 2000
    testbed = Testbed(only_command_path(stall_rate=0.02, stall_steps=1.0), n, DT)
    stalled = sum(int((testbed.actuate(np.full((2, n), 0.1))[0] > 0.15).sum()) for _ in range(draws))
    assert abs(stalled / (n * draws) - 0.02) < 4 * math.sqrt(0.02 * 0.98 / (n * draws))
    np.random.seed(4)
    Testbed(only_command_path(stall_rate=0.02, stall_steps=1.0), 3, DT).actuate(np.zeros((2, 3)))
    after_one = np.random.rand()
    np.random.seed(4)
    Testbed(only_command_path(stall_rate=0.02, stall_steps=1.0), 3, DT).actuate(np.ones((2, 3)))
    assert np.random.rand() == after_one  # one draw per robot and iteration, whatever happens


def test_the_verifier_counts_true_poses_not_the_noisy_ones() -> None:
    model = only_command_path(noise_along_m=0.02)
    u = np.zeros((50, 2, 1))
    np.random.seed(2)
    r = Robotarium(
        number_of_robots=1,
        show_figure=False,
        sim_in_real_time=False,
        initial_conditions=np.array([[1.59], [0.0], [0.0]]),
        skip_initialization=True,
        testbed_model=model,
    )
    seen = []
    for step in u:
        seen.append(r.get_poses()[0, 0])
        r.set_velocities(np.arange(1), step)
        r.step()
    assert max(seen) > 1.6  # the noisy pose left the arena ...
    assert r.errors['robots_outside_boundaries'] == 0  # ... the true one did not


def test_a_scale_multiplies_delay_and_lag_only() -> None:
    doubled = named_model('fitted:2')
    assert (
        doubled.delay_v_steps == 2 * FITTED.delay_v_steps and doubled.delay_omega_steps == 2 * FITTED.delay_omega_steps
    )
    assert doubled.lag_s == 2 * FITTED.lag_s and doubled.name == 'fitted:2'
    assert replace(doubled, name='fitted', delay_v_steps=0, delay_omega_steps=0, lag_s=0) == replace(
        FITTED, delay_v_steps=0, delay_omega_steps=0, lag_s=0
    )
    assert named_model('fitted') is FITTED and named_model('ideal').is_ideal and not FITTED.is_ideal
    assert named_model('fitted:0.5').lag_s == FITTED.lag_s / 2


@pytest.mark.parametrize(
    'name', ['', 'real', 'fitted:', 'fitted:0', 'fitted:-1', 'fitted:two', 'fitted:inf', 'ideal:2']
)
def test_bad_names_are_refused_with_the_accepted_forms(name: str) -> None:
    with pytest.raises(TestbedModelError, match=r"'ideal', 'fitted' or 'fitted:K' with K > 0") as error:
        named_model(name)
    assert isinstance(error.value, ValueError)
    with pytest.raises(ValueError, match='fitted:K'):
        Robotarium(number_of_robots=1, show_figure=False, skip_initialization=True, testbed_model=name)
