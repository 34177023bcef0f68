"""The bundled Robotarium simulator against the PyPI simulator and the rps contract."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from robotarium_exp.rps.errors import RobotariumError
from robotarium_exp.rps.robotarium import Robotarium
from robotarium_exp.rps_alias import seed_rps

NOT_A_BOOL: Any = 'yes'  # a wrong argument type, passed on purpose (Any, so mypy lets it through)


def ours(n: int = 2, ic: np.ndarray | None = None, **kwargs) -> Robotarium:
    ic = np.array([[0.0, 0.5], [0.0, 0.0], [0.0, 0.0]])[:, :n] if ic is None else ic
    return Robotarium(
        number_of_robots=n,
        show_figure=False,
        sim_in_real_time=False,
        initial_conditions=ic,
        skip_initialization=True,
        **kwargs,
    )


def test_documented_difference_per_wheel_clipping() -> None:
    """The testbed clips each wheel (ours too); the PyPI simulator only clips v and omega separately."""
    r = ours(1, np.zeros((3, 1)))
    r.get_poses()
    r.set_velocities(np.arange(1), np.array([[0.2], [2.0]]))  # wheels (0.4 -/+ 0.22) / 0.032 = 5.6, 19.4 rad/s
    r.step()
    wheels = np.clip([(0.4 - 0.22) / 0.032, (0.4 + 0.22) / 0.032], -12.5, 12.5)
    v, omega = 0.016 * wheels.sum() / 2, 0.016 / 0.11 * (wheels[1] - wheels[0])
    np.testing.assert_allclose(r.get_poses()[:, 0], [0.033 * v, 0.0, 0.033 * omega], atol=1e-15)
    assert r.errors['exceeded_actuator_limits'] == 1
    rps_robotarium = pytest.importorskip('rps.robotarium')
    pypi = rps_robotarium.Robotarium(
        number_of_robots=1, show_figure=False, sim_in_real_time=False, initial_conditions=np.zeros((3, 1))
    )
    pypi.get_poses()
    pypi.set_velocities(np.arange(1), np.array([[0.2], [2.0]]))
    pypi.step()
    np.testing.assert_allclose(pypi.get_poses()[:, 0], [0.033 * 0.2, 0.0, 0.033 * 2.0], atol=1e-15)  # unclipped


def test_validation_counts_like_v2(capsys) -> None:
    # two robots 0.13 m apart facing each other: shifted centres 0.08 m apart -> too close, once per pair-step
    r = ours(2, np.array([[0.0, 0.13], [0.0, 0.0], [0.0, np.pi]]))
    for _ in range(2):
        r.get_poses()
        r.step()
    assert r.errors == {'robots_outside_boundaries': 0, 'robots_too_close': 2, 'exceeded_actuator_limits': 0}
    r.debug()
    out = capsys.readouterr().out
    assert 'took approximately 0.07 real seconds' in out and 'Errors detected, your script will NOT run' in out
    assert 'Simulation had 2 time steps where robots were too close (potential collision).' in out
    outside = ours(1, np.array([[1.65], [0.0], [0.0]]))
    outside.get_poses()
    outside.step()
    assert outside.errors['robots_outside_boundaries'] == 1
    outside.debug()
    assert 'Simulation had 1 time steps where robots were outside boundaries.' in capsys.readouterr().out
    fast = ours(1, np.zeros((3, 1)))
    for _ in range(4):
        fast.get_poses()
        fast.set_velocities(np.arange(1), np.array([[0.3], [0.0]]))  # 18.75 rad/s per wheel
        fast.step()
    fast.debug()
    out = capsys.readouterr().out
    assert 'No hard errors detected, your script will run on the Robotarium!' in out
    assert 'WARNING: 4 out of 4 (~100%) timesteps had velocity command(s) exceed actuator limits.' in out
    clean = ours(1, np.zeros((3, 1)))
    clean.get_poses()
    clean.step()
    clean.debug()
    assert (
        'No errors or warnings in your simulation!  Your script will run on the Robotarium!' in capsys.readouterr().out
    )


def test_constants_are_v2s() -> None:
    r = ours(1, np.zeros((3, 1)))
    assert r.TIME_STEP == 0.033 and r.BASE_LENGTH == 0.11 and r.WHEEL_RADIUS == 0.016
    np.testing.assert_array_equal(r.BOUNDARIES * 0.5, [-0.8, 0.8, -0.5, 0.5])  # an array, as V2's
    assert r.MAX_WHEEL_VELOCITY == pytest.approx(12.5) and r.MAX_ANGULAR_VELOCITY == pytest.approx(3.636, abs=1e-3)


@pytest.mark.parametrize(
    ('make', 'match'),
    [
        (
            lambda: Robotarium(number_of_robots=np.int64(3), sim_in_real_time=False),
            'NumberOfRobots must be an integer. Received type int64.',
        ),
        (lambda: Robotarium(number_of_robots=51, sim_in_real_time=False), r'Number of robots must be >= 0 and <= 50'),
        (
            lambda: Robotarium(
                number_of_robots=2,
                sim_in_real_time=False,
                initial_conditions=np.zeros((2, 2)),
                skip_initialization=True,
            ),
            r'initial_conditions must be a 3 x 2 array .* got shape \(2, 2\)',
        ),
        (
            lambda: Robotarium(number_of_robots=2, show_figure=NOT_A_BOOL),
            'ShowFigure must be a boolean. Received type str.',
        ),
        (
            lambda: Robotarium(number_of_robots=2, initial_conditions=[[0.0], [0.0], [0.0]]),
            'InitialConditions must be a numpy ndarray. Received type list.',
        ),
        (
            lambda: Robotarium(
                number_of_robots=30,
                sim_in_real_time=False,
                initial_conditions=np.vstack([np.mgrid[-1:1:6j, -0.8:0.8:5j].reshape(2, -1), np.zeros(30)]),
            ),
            '22 charger slots',
        ),
    ],
)
def test_bad_construction_raises_what_rps_users_know(make, match: str) -> None:
    with pytest.raises(AssertionError, match=match):
        make()


def test_unknown_keywords_are_ignored_with_a_warning_as_v2_ignores_them() -> None:
    with pytest.warns(UserWarning, match=r"ignores the unknown keyword\(s\) \['show_figures'\]"):
        r = Robotarium(number_of_robots=1, sim_in_real_time=False, skip_initialization=True, show_figures=True)
    assert r.show_figure is False
    with pytest.raises(TypeError):  # positional arguments are not V2's interface (its __init__ takes **kwargs)
        Robotarium(1, False)  # type: ignore[misc]


def test_call_order_is_enforced() -> None:
    r = ours()
    r.get_poses()
    with pytest.raises(AssertionError, match=r'Can only call get_poses\(\) once per call of step\(\)!') as caught:
        r.get_poses()
    assert caught.type is AssertionError  # V2's assert: the same last traceback line
    r.step()
    with pytest.raises(AssertionError, match=r'Make sure you call get_poses before calling step\(\)!') as caught:
        r.step()
    assert caught.type is AssertionError
    with pytest.raises(RobotariumError, match=r'2xk array .* got shape \(3, 2\)'):
        r.set_velocities(np.arange(2), np.zeros((3, 2)))
    with pytest.raises(
        AssertionError, match=r'Column count of velocities \(3\) must be <= number_of_robots \(2\)'
    ) as caught:
        r.set_velocities(np.arange(2), np.zeros((2, 3)))
    assert caught.type is AssertionError
    # what V2 does not check is a refusal of ours: RobotariumError, still an AssertionError
    with pytest.raises(RobotariumError, match='must be finite'):
        r.set_velocities(np.arange(2), np.array([[0.1, np.nan], [0.0, 0.0]]))
    poses = r.get_poses()
    poses[0] += 5.0  # a copy: changing it does not move the robots (V2)
    r.step()
    assert r.get_poses()[0, 0] == 0.0


def test_initialization_drives_robots_from_the_chargers_to_the_initial_conditions() -> None:
    ic = np.array([[-1.0, 0.0, 1.0], [0.0] * 3, [0.0] * 3])
    seed_rps(3)
    r = Robotarium(number_of_robots=3, sim_in_real_time=False, initial_conditions=ic)
    poses = r.get_poses()
    assert np.hypot(*(poses[:2] - ic[:2])).max() <= 0.05
    assert np.abs(np.angle(np.exp(1j * (poses[2] - ic[2])))).max() <= 0.2
    assert r.iterations == r.initialization_steps > 100  # they count towards the duration
    assert r.errors['robots_too_close'] == 0  # and are not validated


# V2's own run of this loop (poses at steps 300 and 599, encoder counts at the end, np.random seeded with 0),
# recorded by running the official simulator: numbers, not its code.
V2_POSES_300 = [
    [-1.6085876645005197, -0.4416531000670372, 0.07569255700819386, -0.08994821127470919, 0.8305421892725577],
    [0.38549353369416545, -0.15909463051843123, 0.9267622718252739, 0.19134970277454197, 0.48665559783753193],
    [1.6182725837933556, 1.2097857545887494, -2.5146414438881433, 1.2322693551847386, -0.8364046979344976],
]
V2_POSES_599 = [
    [-1.360186740612, -0.42851762037698227, 0.3910636864703656, 0.2708358865153331, 0.7104752502616573],
    [0.23727635331383592, 0.22844003017839898, 0.3492132112738552, 0.14377996357025596, 0.7568185817221518],
    [2.654898675344493, 1.442880131437633, 2.4276917981332824, -0.00558517073666643, -1.1954969195960021],
]
V2_ENCODERS = [[-940, 6528, 5620, 2404, -6239], [7268, 7912, -286, -6955, -8290]]


def test_the_same_commands_give_v2s_poses_and_encoder_counts() -> None:
    """600 steps of commands over the wheel and turn limits, no barriers: poses to 1e-9 of V2's, counts equal."""
    np.random.seed(0)
    ic = np.array([[-1.0, -0.5, 0.0, 0.5, 1.0], [0.2, -0.3, 0.4, -0.1, 0.3], [0.0, 1.0, -2.0, 3.0, -0.5]])
    r = ours(5, ic)
    seen = []
    for k in range(600):
        seen.append(r.get_poses())
        t = k * 0.033
        r.set_velocities(
            np.arange(5), np.vstack([0.25 * np.sin(t + np.arange(5)), 4.0 * np.cos(0.7 * t + np.arange(5))])
        )
        r.step()
    np.testing.assert_allclose(seen[300], V2_POSES_300, atol=1e-9)
    np.testing.assert_allclose(seen[599], V2_POSES_599, atol=1e-9)
    np.testing.assert_array_equal(r.get_encoders(), V2_ENCODERS)  # the noise draws are V2's, in V2's order


# V2's initialization of one robot (no barrier QP for a single robot, so nothing but V2's algorithm and draws):
# steps taken, pose and encoder counts at the end, for random.seed and np.random.seed 0 and 1, recorded by
# running the official simulator.
V2_SINGLE_ROBOT_INITIALIZATION = {
    0: (352, [0.3002092069202918, 0.18022136106543116, 2.321504509382016], [30295, 32611]),
    1: (512, [0.2843105215559242, 0.18811473317811148, 2.318266174480961], [45939, 48270]),
}


@pytest.mark.parametrize('seed', sorted(V2_SINGLE_ROBOT_INITIALIZATION))
def test_the_initialization_is_v2s_step_for_step(seed: int) -> None:
    steps, pose, encoders = V2_SINGLE_ROBOT_INITIALIZATION[seed]
    seed_rps(seed)
    r = Robotarium(number_of_robots=1, sim_in_real_time=False, initial_conditions=np.array([[0.3], [0.2], [2.5]]))
    assert r.iterations == r.initialization_steps == steps
    np.testing.assert_allclose(r.get_poses()[:, 0], pose, atol=1e-12)
    np.testing.assert_array_equal(r.get_encoders()[:, 0], encoders)
