"""Delay compensation: the lag's response against its closed form and quadrature, the predictor against plants
simulated independently (exactly for a whole-period delay, finely integrated for a fractional delay with a lag),
and the swarm step acting on the predicted positions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.onboard.delay import CommandPredictor, lag_response
from vtube_planning.onboard.stepper import SwarmStep
from vtube_planning.params import ControlParams, SwarmParams

DT = 0.033


def test_the_lag_response_is_the_closed_form_and_its_mean_the_integral() -> None:
    rng = np.random.default_rng(0)
    u, v0 = rng.normal(size=(2, 5)), rng.normal(size=(2, 5))
    h, tau = 0.05, 0.19
    mean, end = lag_response(u, v0, h, tau)
    np.testing.assert_allclose(end, u + (v0 - u) * math.exp(-h / tau), rtol=1e-14)
    t = np.linspace(0.0, h, 20001)  # the trapezoid rule over the closed form v(t)
    v = u[..., None] + (v0 - u)[..., None] * np.exp(-t / tau)
    np.testing.assert_allclose(mean, np.trapezoid(v, t, axis=-1) / h, rtol=1e-8)
    without = lag_response(u, v0, h, 0.0)
    assert without[0] is u and without[1] is u  # no lag: the command itself


@pytest.mark.parametrize('delay', [1, 2, 5])
def test_a_whole_period_delay_is_predicted_exactly(delay: int) -> None:
    """The plant p[k+1] = p[k] + dt u[k - delay] (the initial velocity before the first command arrives): at every
    period the prediction is where the robots are ``delay`` periods later, whatever is commanded meanwhile."""
    rng = np.random.default_rng(delay)
    n, periods = 4, 30
    v0 = rng.normal(size=(2, n))
    commands = rng.normal(size=(periods, 2, n))
    applied = np.concatenate([np.broadcast_to(v0, (delay, 2, n)), commands])[:periods]
    positions = np.concatenate([np.zeros((1, 2, n)), DT * np.cumsum(applied, axis=0)])
    predictor = CommandPredictor(n, delay, 0.0, DT, v0)
    for k in range(periods - delay):
        np.testing.assert_allclose(predictor.predict(positions[k]), positions[k + delay], atol=1e-12)
        predictor.sent(commands[k])


def fine_plant(commands: np.ndarray, v0: np.ndarray, delay: float, lag: float, t_end: float) -> np.ndarray:
    """Position at ``t_end`` of the plant (delay, then lag, then integration), by explicit Euler at 1/2000 period."""
    h = DT / 2000
    v, p = v0.copy(), np.zeros_like(v0)
    for j in range(round(t_end / h)):
        k = math.floor(((j + 0.5) * h) / DT - delay)
        u = v0 if k < 0 else commands[min(k, len(commands) - 1)]
        v = v + (h / lag) * (u - v)
        p = p + h * v
    return p


@pytest.mark.parametrize('delay', [4.5, 4.37, 0.3, 2.0])
def test_a_fractional_delay_with_a_lag_is_predicted_by_the_plant(delay: float) -> None:
    """The testbed's delay (4.5 periods), delays off any grid (4.37, under a period) and a whole one, with the lag
    (0.19 s): after 12 periods of random commands, then the last one held, the prediction is where the finely
    integrated plant is a delay and a lag later; the commands switch where the plant switches them."""
    rng = np.random.default_rng(7)
    n, lag = 3, 0.19
    v0 = rng.normal(size=(2, n))
    commands = rng.normal(size=(12, 2, n))
    predictor = CommandPredictor(n, delay, lag, DT, v0)
    for command in commands:
        predictor.sent(command)
    now = fine_plant(commands, v0, delay, lag, 12 * DT)
    later = fine_plant(commands, v0, delay, lag, 12 * DT + delay * DT + lag)
    np.testing.assert_allclose(predictor.predict(now), later, atol=2e-4 * np.abs(later - now).max())


def test_a_predictor_refuses_a_negative_delay_or_lag() -> None:
    with pytest.raises(ValueError, match='delay_steps >= 0, lag_s >= 0 and dt_s > 0'):
        CommandPredictor(2, -1.0, 0.0, DT)
    with pytest.raises(ValueError, match='delay_steps >= 0, lag_s >= 0 and dt_s > 0'):
        CommandPredictor(2, 1.0, -0.1, DT)


def test_the_compensating_step_commands_what_the_plain_step_commands_where_the_robots_will_be() -> None:
    """With a delay to compensate, the step's command at the robots' positions is the plain step's command at the
    positions a predictor fed the same commands expects; what the caller sent (``sent``) replaces the step's."""
    tube = VirtualTube(ArcPath((ArcPiece(50.0),)), WidthProfile(4.0, (WidthPart('constant', 50.0),)))
    swarm = SwarmParams(n_robots=4)
    compensating = ControlParams(compensate_delay_steps=3.0).step_params(swarm)
    step = SwarmStep(tube, compensating, 4, constant_speed_mps=3.0, warm_projection=False)
    plain = SwarmStep(tube, ControlParams().step_params(swarm), 4, constant_speed_mps=3.0, warm_projection=False)
    oracle = CommandPredictor(4, 3.0, 0.0, 0.1)
    rng = np.random.default_rng(3)
    points = np.array([[5.0, 5.5, 6.0, 6.5], [0.0, 1.0, -1.0, 0.5]])
    for k in range(6):
        result = step(points, 0.1)
        expected = plain(oracle.predict(points), 0.1)
        np.testing.assert_allclose(result.velocity, expected.velocity, atol=1e-12)
        sent = result.velocity + (0.3 * rng.normal(size=result.velocity.shape) if k % 2 else 0.0)
        step.sent(sent)
        oracle.sent(sent)
        points = points + 0.1 * sent
    assert step.predictor is not None and plain.predictor is None
