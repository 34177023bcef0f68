"""V2's distance sensors and obstacles in the bundled simulator."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.rps.robotarium import Robotarium
from robotarium_exp.rps.robotarium_abc import ARobotarium
from robotarium_exp.rps.utilities.sensors import simulate_distance_sensors, simulate_distance_sensors_without_robots

MOUNTS = ARobotarium.DISTANCE_SENSORS_ORIENTATION
WALL_X = np.array([[[0.5, -1.0], [0.5, 1.0]]])  # a vertical wall at x = 0.5
CEILING = np.array([[[-1.0, 0.3], [1.0, 0.3]]])  # a horizontal wall at y = 0.3


def noiseless(poses: np.ndarray, obstacles: np.ndarray | None) -> np.ndarray:
    return simulate_distance_sensors(poses, obstacles, MOUNTS, 0.11, 0.01, 1.2, 0.0, 0.0, 0.0)


def test_walls_are_read_at_their_distance_from_each_sensor() -> None:
    """Hand geometry: the body centre is 0.01 m ahead of the axle and the sensors are mounted around it."""
    d = noiseless(np.zeros((3, 1)), np.concatenate([WALL_X, CEILING]))
    assert d[3, 0] == pytest.approx(0.5 - 0.01 - 0.05)  # straight ahead, mounted 0.05 m forward
    assert d[1, 0] == pytest.approx(0.3 - 0.06)  # to the left, mounted 0.06 m to the left
    # 45 degrees to the left from (0.05, 0.05): the ceiling is 0.25 m up, the wall 0.44 m across -> ceiling first
    assert d[2, 0] == pytest.approx(0.25 * np.sqrt(2))
    assert d[0, 0] == -1.0 and d[6, 0] == -1.0  # backwards: nothing within 1.2 m
    far = noiseless(np.zeros((3, 1)), np.array([[[1.3, -1.0], [1.3, 1.0]]]))
    assert far[3, 0] == -1.0  # 1.24 m away: beyond the range


def test_other_robots_are_discs_of_the_robot_diameter() -> None:
    """Robot B faces robot A 0.3 m ahead: A's front sensor meets B's disc (radius 0.055 around B's body centre)."""
    poses = np.array([[0.0, 0.3], [0.0, 0.0], [0.0, np.pi]])
    d = noiseless(poses, None)
    a_sensor, b_centre = 0.01 + 0.05, 0.3 - 0.01
    assert d[3, 0] == pytest.approx(b_centre - 0.055 - a_sensor)
    assert d[3, 1] == pytest.approx(d[3, 0])  # symmetric
    off_axis = noiseless(np.array([[0.0, 0.3], [0.0, 0.05], [0.0, np.pi]]), None)
    chord = np.sqrt(0.055**2 - 0.05**2)  # the ray passes 0.05 m from B's centre
    assert off_axis[3, 0] == pytest.approx(b_centre - chord - a_sensor)
    blind = simulate_distance_sensors_without_robots(poses, None, MOUNTS, 1.2, 0.0, 0.0, 0.0)
    assert np.all(blind == -1.0)  # the variant without robots sees only obstacles


def test_readings_equal_v2s_noise_draws() -> None:
    """V2's readings for three robots, two walls, np.random.seed(5), dropout and outlier probabilities 0.2,
    recorded by running the official simulator (numbers, not its code)."""
    v2 = [
        [-1.0, 0.373078680772, -1.0],
        [0.590296780734, -1.0, 0.809137680469],
        [0.644242742516, -1.0, 0.693195429756],
        [0.096889522518, -1.0, -1.0],
        [0.755162692329, 0.556383329713, -1.0],
        [-1.0, 0.489018023881, -1.0],
        [-1.0, -1.0, -1.0],
    ]
    poses = np.array([[0.0, 0.3, -0.4], [0.0, 0.05, 0.3], [0.2, 2.9, -1.2]])
    walls = np.array([[[0.7, -0.9], [0.7, 0.9]], [[-1.0, 0.6], [1.0, 0.6]]])
    np.random.seed(5)
    got = simulate_distance_sensors(poses, walls, MOUNTS, 0.11, 0.01, 1.2, 0.03, 0.2, 0.2)
    np.testing.assert_allclose(got, v2, atol=1e-11)


def test_the_simulator_reads_the_sensors_every_step_and_places_their_endpoints() -> None:
    np.random.seed(0)  # this seed keeps robot 0's front reading (no dropout, no outlier)
    r = Robotarium(
        number_of_robots=2,
        sim_in_real_time=False,
        skip_initialization=True,
        initial_conditions=np.array([[0.0, -0.8], [0.0, -0.6], [0.0, 0.0]]),
        use_distance_sensors=True,
        obstacles=WALL_X,
    )
    assert np.all(np.isnan(r.get_distances()))  # before the first step, as V2
    r.get_poses()
    r.step()
    d, ends, poses = r.get_distances(), r.get_distance_endpoints(), r.get_poses()
    assert d.shape == (7, 2) and ends.shape == (2, 7, 2)
    seen = d >= 0
    assert abs(d[3, 0] - 0.44) < 0.44 * 0.03 * 4  # the wall, with 3 % noise
    assert np.array_equal(np.isnan(ends[0]), ~seen)
    theta = poses[2][None, :] + MOUNTS[2][:, None]
    c, s = np.cos(poses[2]), np.sin(poses[2])
    start_x = c * MOUNTS[0][:, None] - s * MOUNTS[1][:, None] + poses[0]
    np.testing.assert_allclose(ends[0][seen], (start_x + d * np.cos(theta))[seen], atol=1e-12)
    plain = Robotarium(number_of_robots=1, sim_in_real_time=False, skip_initialization=True)
    plain.get_poses()
    plain.step()
    assert np.all(np.isnan(plain.get_distances()))  # without distance sensors: NaN, as V2


def test_obstacles_rays_and_endpoints_are_drawn_headless() -> None:
    pytest.importorskip('matplotlib')
    import matplotlib

    matplotlib.use('Agg')
    r = Robotarium(
        number_of_robots=2,
        show_figure=True,
        sim_in_real_time=False,
        skip_initialization=True,
        initial_conditions=np.array([[0.0, -0.8], [0.0, -0.6], [0.0, 0.0]]),
        use_distance_sensors=True,
        obstacles=np.concatenate([WALL_X, CEILING]),
        show_distance_rays=True,
    )
    r.get_poses()
    r.step()
    ax = r._axes_handle
    assert len(ax.lines) == 2  # the two obstacles
    assert len(ax.collections[-1].get_segments()) == 14  # a ray per sensor
    shown = r._endpoint_handle.get_offsets()
    assert np.isfinite(shown).all(axis=1).sum() == int((r.get_distances() >= 0).sum())
    import matplotlib.pyplot as plt

    plt.close(r._fig)


def test_the_verifier_does_not_count_obstacles_as_v2() -> None:
    """V2's verifier knows robots and the arena only: driving through an obstacle segment counts nothing."""
    r = Robotarium(
        number_of_robots=1,
        sim_in_real_time=False,
        skip_initialization=True,
        initial_conditions=np.array([[0.3], [0.0], [0.0]]),
        obstacles=WALL_X,
    )
    for _ in range(40):  # 0.2 m/s for 1.3 s: through the wall at x = 0.5
        r.get_poses()
        r.set_velocities(np.arange(1), np.array([[0.2], [0.0]]))
        r.step()
    assert r.get_poses()[0, 0] > 0.5
    assert r.errors == {'robots_outside_boundaries': 0, 'robots_too_close': 0, 'exceeded_actuator_limits': 0}


def test_on_board_sensors_read_as_v2_models_them() -> None:
    """Encoders count wheel turns through the gear; gyro, orientation and magnetometer follow the motion."""
    from robotarium_exp.rps.robotarium import Robotarium

    np.random.seed(1)
    r = Robotarium(
        number_of_robots=1,
        sim_in_real_time=False,
        initial_conditions=np.array([[0.0], [0.0], [0.0]]),
        skip_initialization=True,
    )
    for _ in range(100):
        r.get_poses()
        r.set_velocities(np.arange(1), np.array([[0.1], [0.5]]))
        r.step()
    wheels = np.array([2 * 0.1 - 0.11 * 0.5, 2 * 0.1 + 0.11 * 0.5]) / (2 * 0.016)  # rad/s
    expected = wheels * 100 * r.TIME_STEP * 28 * 100.37 / (2 * np.pi)
    np.testing.assert_allclose(r.get_encoders()[:, 0], expected, rtol=0.01)  # noise: about 0.25 sqrt(n) per step
    assert abs(r.get_gyros()[2, 0] - 0.5) < 0.01
    heading = np.degrees(r.get_poses()[2, 0]) % 360.0
    assert abs(r.get_orientations()[0] - heading) < 1.5
    assert np.all(np.isnan(r.get_distances())) and r.get_distances().shape == (7, 1)
    assert abs(r.get_accelerations()[2, 0] + 9.81) < 0.3
