"""The classic ``rps`` generation (``robotarium_exp.rps_classic``): constants, messages, report, laws, the alias.

The expected texts are the official classic simulator's output (PyPI ``robotarium_python_simulator`` 0.0.0, run
under numpy 1.26); the laws are checked against hand computations, robot by robot, on random states.
"""

from __future__ import annotations

import numpy as np
import pytest

import robotarium_exp.rps_classic.utilities.misc as classic_misc
from robotarium_exp.rps_classic import robotarium_abc
from robotarium_exp.rps_classic.robotarium import Robotarium


def headless(ic: np.ndarray) -> Robotarium:
    return Robotarium(number_of_robots=ic.shape[1], show_figure=False, sim_in_real_time=False, initial_conditions=ic)


# ---------------------------------------------------------------------- the simulator


def test_classic_constants_are_instance_attributes() -> None:
    ic = np.zeros((3, 2))
    ic[0, 1] = 0.5
    r = headless(ic)
    assert r.time_step == 0.033 and r.boundaries == [-1.6, -1, 3.2, 2]
    assert (r.robot_diameter, r.wheel_radius, r.base_length, r.max_linear_velocity) == (0.11, 0.016, 0.105, 0.2)
    assert r.max_wheel_velocity == pytest.approx(12.5) and r.robot_radius == pytest.approx(0.055)
    assert r.max_angular_velocity == pytest.approx(2 * 0.2 / 0.11)
    assert r.get_poses() is ic  # the caller's array itself, updated in place
    assert not hasattr(r, 'TIME_STEP') and not hasattr(r, 'debug')


def test_report_text_and_counts_as_classic_prints_them(capsys) -> None:
    # three robots: 0 and 1 closer than 0.11 m, 2 outside the arena and (first 5 steps) over the wheel limit
    r = headless(np.array([[0.0, 0.05, 1.7], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]))
    for k in range(40):
        r.get_poses()
        r.set_velocities(np.arange(3), np.array([[0.0, 0.0, 0.2], [0.0, 0.0, 3.0 if k < 5 else 0.0]]))
        r.step()
    r.call_at_scripts_end()
    assert capsys.readouterr().out == (
        '##### DEBUG OUTPUT #####\n'
        'Your simulation will take approximately 2 real seconds when deployed on the Robotarium. \n\n'
        '\t Simulation had 40 iteration(s) robots were outside the boundaries.\n\n'
        '\t Simulation had 40 iteration(s) where robots collided.\n\n'
        '\t Simulation had 5 iteration(s) where the actuator limits were exceeded.\n'
    )
    second = headless(np.zeros((3, 1)))  # classic's counters are shared: the first run's counts carry over
    second.get_poses()
    second.step()
    second.call_at_scripts_end()
    out = capsys.readouterr().out
    assert 'approximately 1 real seconds' in out and 'had 40 iteration(s) robots were outside' in out


def test_clean_report(capsys) -> None:
    r = headless(np.zeros((3, 1)))
    r.get_poses()
    r.step()
    r.call_at_scripts_end()
    assert capsys.readouterr().out.endswith('No errors in your simulation! Acceptance of your experiment is likely!\n')


def test_set_velocities_clips_v_and_omega_in_place_and_never_the_wheels() -> None:
    r = headless(np.zeros((3, 1)))
    r.get_poses()
    command = np.array([[0.5], [2.0]])  # wheels (1.0 -/+ 0.21) / 0.032: 24.7 and 37.8 rad/s, left unclipped
    r.set_velocities(np.arange(1), command)
    assert command[0, 0] == 0.2 and command[1, 0] == 2.0  # the caller's array
    r.step()
    np.testing.assert_allclose(r.get_poses()[:, 0], [0.033 * 0.2, 0.0, 0.033 * 2.0], atol=1e-15)
    assert robotarium_abc.SHARED_ERRORS['actuator'] == 1


@pytest.mark.parametrize(
    ('kwargs', 'message'),
    [
        (
            {'number_of_robots': 2.0},
            (
                'The number of robots used argument (number_of_robots) provided to create the Robotarium object must be '
                "an integer type. Recieved type 'float'."
            ),
        ),
        (
            {'number_of_robots': 51},
            (
                'Requested 51 robots to be used when creating the Robotarium object. The deployed number of robots must '
                'be between 0 and 50.'
            ),
        ),
        (
            {'number_of_robots': 2, 'initial_conditions': np.zeros((2, 2))},
            (
                'Initial conditions provided when creating the Robotarium object must of size 3xN, where N is the number '
                'of robots used. Expected a 3 x 2 array but recieved a 2 x 2 array.'
            ),
        ),
        (
            {'number_of_robots': 2, 'initial_conditions': [1]},
            (
                'The initial conditions array argument (initial_conditions) provided to create the Robotarium object '
                "must be a numpy ndarray. Recieved type 'list'."
            ),
        ),
        (
            {'number_of_robots': 2, 'show_figure': 1},
            (
                'The display figure window argument (show_figure) provided to create the Robotarium object must be '
                "boolean type. Recieved type 'int'."
            ),
        ),
        (
            {'number_of_robots': 2, 'show_figure': False, 'sim_in_real_time': 1},
            (
                'The simulation running at 0.033s per loop (sim_real_time) provided to create the Robotarium object '
                "must be boolean type. Recieved type 'bool'."
            ),
        ),
        ({}, 'Requested -1 robots'),
    ],
)
def test_constructor_assertions_have_classic_texts(kwargs: dict, message: str) -> None:
    with pytest.raises(AssertionError) as caught:
        Robotarium(**kwargs)
    assert caught.type is AssertionError and str(caught.value).startswith(message)


def test_call_order_messages() -> None:
    r = headless(np.zeros((3, 1)))
    with pytest.raises(AssertionError, match=r'^Make sure to call get_poses before calling step\(\) again\.$'):
        r.step()
    r.get_poses()
    with pytest.raises(AssertionError, match=r'^Can only call get_poses\(\) once per call of step\(\)\.$') as caught:
        r.get_poses()
    assert caught.type is AssertionError


def test_random_initial_conditions_are_classic_grid_cells() -> None:
    np.random.seed(11)
    poses = classic_misc.generate_initial_conditions(6, spacing=0.5, width=2.5, height=1.5)
    np.random.seed(11)
    cells = np.random.choice(5 * 3, 6, replace=False) + 1  # 5 columns x 3 rows, cells counted from 1
    expected = [[c // 3 * 0.5 - 1.25, c % 3 * 0.5 - 0.75, np.random.rand() * 2 * np.pi - np.pi] for c in cells]
    np.testing.assert_allclose(poses, np.array(expected).T, atol=1e-15)


# ---------------------------------------------------------------------- controllers and transformations


# ---------------------------------------------------------------------- barrier certificates


# ---------------------------------------------------------------------- the alias


# ---------------------------------------------------------------------- the testbed model (beyond classic)


def _classic_flight(model: object, steps: int = 30) -> tuple[np.ndarray, np.ndarray, Robotarium]:
    """Poses handed out and true poses over ``steps`` random commands within the limits, from a fixed start."""
    from dataclasses import replace

    from robotarium_exp.rps.testbed_model import IDEAL

    rng = np.random.default_rng(4)
    extra = (
        {}
        if model is None
        else {'testbed_model': replace(IDEAL, name='k', **model) if isinstance(model, dict) else model}
    )
    r = Robotarium(2, False, False, np.array([[0.0, 0.5], [0.0, 0.2], [0.0, 1.0]]), **extra)
    seen, true = [], []
    for _ in range(steps):
        seen.append(r.get_poses().copy())
        r.set_velocities(np.arange(2), np.vstack([rng.uniform(0, 0.1, 2), rng.uniform(-1, 1, 2)]))
        r.step()
        true.append(r.poses.copy())
    return np.array(seen), np.array(true), r


def test_the_ideal_testbed_model_is_classic_bit_for_bit() -> None:
    seen, true, _ = _classic_flight(None)
    seen_ideal, true_ideal, ideal = _classic_flight('ideal')
    np.testing.assert_array_equal(seen_ideal, seen)
    np.testing.assert_array_equal(true_ideal, true)
    assert ideal.get_poses() is ideal.poses  # still the array itself


def test_a_testbed_delay_of_k_iterations_shifts_classic_motion_by_k_steps() -> None:
    _, ideal, _ = _classic_flight('ideal')
    _, delayed, r = _classic_flight({'delay_v_steps': 3.0, 'delay_omega_steps': 3.0})
    np.testing.assert_allclose(delayed[3:], ideal[:-3], atol=1e-12)
    assert r.get_poses() is not r.poses  # a model's poses are a copy
