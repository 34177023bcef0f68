"""rps.utilities names of V2: graph Laplacians, position and pose controllers, random positions, the QP helper."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.errors import RobotariumError
from robotarium_exp.rps.utilities import graph
from robotarium_exp.rps.utilities.barrier_certificates import _solve_qp
from robotarium_exp.rps.utilities.controllers import (
    create_pose_controller_clf,
    create_pose_parking_controller_clf,
    create_uni_position_controller,
)
from robotarium_exp.rps.utilities.misc import generate_random_poses, generate_random_positions


def is_laplacian(lap: np.ndarray) -> bool:
    off = lap - np.diag(np.diag(lap))
    return bool(np.allclose(lap, lap.T) and np.allclose(lap.sum(axis=1), 0) and set(np.unique(off)) <= {-1.0, 0.0})


def connected(lap: np.ndarray) -> bool:
    return int(np.sum(np.linalg.eigvalsh(lap) < 1e-9)) == 1  # one zero eigenvalue


def test_named_graphs_have_their_degrees() -> None:
    for n in (3, 4, 7):
        for lap, degrees in (
            (graph.completeGL(n), np.full(n, n - 1)),
            (graph.cycleGL(n), np.full(n, 2)),
            (graph.lineGL(n), np.r_[1, np.full(n - 2, 2), 1]),
        ):
            assert is_laplacian(lap) and connected(lap)
            np.testing.assert_array_equal(np.diag(lap), degrees)
    np.testing.assert_array_equal(graph.topological_neighbors(graph.cycleGL(5), 0), [1, 4])
    np.testing.assert_array_equal(graph.topological_neighbors(graph.lineGL(5), 4), [3])


def test_random_graphs_follow_numpy_seed_and_their_edge_counts() -> None:
    for seed in range(20):
        np.random.seed(seed)
        lap = graph.random_connectedGL(8, 3)
        assert is_laplacian(lap) and connected(lap) and np.trace(lap) / 2 == 7 + 3  # tree plus 3 edges
        np.random.seed(seed)
        np.testing.assert_array_equal(graph.random_connectedGL(8, 3), lap)  # the script's seed holds
        assert np.trace(graph.randomGL(6, 4)) / 2 == 4 and np.trace(graph.randomGL(4, 99)) / 2 == 6  # capped


def test_delta_disk_neighbors_and_misuse() -> None:
    poses = np.array([[0.0, 0.3, 1.0, 0.0], [0.0, 0.0, 0.0, 0.5], [0.0, 1.0, 2.0, 3.0]])
    np.testing.assert_array_equal(graph.delta_disk_neighbors(poses, 0, 0.5), [1, 3])
    with pytest.raises(RobotariumError, match=r'agent \(4\) must be between 0 and 3\.'):
        graph.delta_disk_neighbors(poses, 4, 0.5)
    with pytest.raises(AssertionError, match='n must be an integer >= 3.'):
        graph.cycleGL(2)


def test_uni_position_controller_drives_the_projection_point_to_the_goal() -> None:
    controller = create_uni_position_controller()
    pose = np.array([[0.0], [0.0], [0.3]])
    goal = np.array([[0.5], [-0.2]])
    for _ in range(600):  # exact unicycle steps of 0.033 s
        v, w = controller(pose, goal)[:, 0]
        pose = pose + 0.033 * np.array([[v * np.cos(pose[2, 0])], [v * np.sin(pose[2, 0])], [w]])
    point = pose[:2, 0] + 0.03 * np.array([np.cos(pose[2, 0]), np.sin(pose[2, 0])])
    np.testing.assert_allclose(point, goal[:, 0], atol=2e-3)


def test_clf_pose_controller_reaches_the_pose_within_the_wheel_limit() -> None:
    controller = create_pose_controller_clf()
    parking = create_pose_parking_controller_clf()
    pose = np.array([[-0.6], [0.3], [2.5]])
    goal = np.array([[0.4], [-0.2], [-1.0]])
    for _ in range(2000):
        dxu = controller(pose, goal)
        wheels = np.abs([dxu[0, 0] / 0.016 - dxu[1, 0] * 0.105 / 0.032, dxu[0, 0] / 0.016 + dxu[1, 0] * 0.105 / 0.032])
        assert wheels.max() <= 10.0 + 1e-9
        v, w = dxu[:, 0]
        pose = pose + 0.033 * np.array([[v * np.cos(pose[2, 0])], [v * np.sin(pose[2, 0])], [w]])
    assert np.hypot(*(pose[:2, 0] - goal[:2, 0])) < 0.05  # the law settles the position (the heading may stall)
    # straight ahead of a goal 1 m away: v = gamma e = 1, omega = 0, scaled to the 10 rad/s wheel limit
    np.testing.assert_allclose(controller(np.zeros((3, 1)), np.array([[1.0], [0.0], [0.0]]))[:, 0], [0.16, 0.0])
    # on the goal, a quarter turn short: v = 0, omega = k alpha (cos alpha = 0) = 4.24 rad/s, over the wheel limit,
    # so scaled to 10 rad/s x 2r / L
    turn = controller(np.array([[0.0], [0.0], [-np.pi / 2]]), np.zeros((3, 1)))[:, 0]
    np.testing.assert_allclose(turn, [0.0, 10.0 * 0.032 / 0.105], atol=1e-12)
    at_goal = np.array([[0.4], [-0.2], [-1.05]])
    np.testing.assert_array_equal(parking(at_goal, goal), 0.0)  # within 5 cm and 0.2 rad: held still
    assert np.any(parking(pose + np.array([[0.2], [0.0], [0.0]]), goal) != 0.0)


def test_random_positions_are_spaced_and_seeded_by_numpy() -> None:
    np.random.seed(3)
    points = generate_random_positions(8, spacing=0.5)
    gaps = np.hypot(*(points[:, :, None] - points[:, None, :]))[np.triu_indices(8, 1)]
    assert points.shape == (2, 8) and gaps.min() >= 0.5 and np.all(np.abs(points[0]) <= 1.5)
    np.random.seed(3)
    np.testing.assert_array_equal(generate_random_poses(8, spacing=0.5)[:2], points)
    with pytest.raises(RobotariumError, match='Cannot fit 40 positions with spacing 0.50 m'):
        generate_random_positions(40, spacing=0.5, width=2.0, height=2.0)


def test_solve_qp_returns_the_projection_or_none() -> None:
    a = np.array([[1.0, 0.0, 0.0, 0.0]])
    np.testing.assert_allclose(
        _solve_qp(2, np.array([[0.3, 0.1], [0.2, -0.1]]), a, np.array([0.1])), [[0.1, 0.1], [0.2, -0.1]]
    )
    assert _solve_qp(1, np.zeros((2, 1)), np.array([[1.0, 0.0], [-1.0, 0.0]]), np.array([-1.0, -1.0])) is None


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
    wheels = r.wheel_speeds(np.array([[0.1], [0.5]]))[:, 0]  # rad/s
    expected = wheels * 100 * r.TIME_STEP * 28 * 100.37 / (2 * np.pi)
    np.testing.assert_allclose(r.get_encoders()[:, 0], expected, rtol=0.01)  # noise: about 0.25 sqrt(n) per step
    assert abs(r.get_gyros()[2, 0] - 0.5) < 0.01
    heading = np.degrees(r.get_poses()[2, 0]) % 360.0
    assert abs(r.get_orientations()[0] - heading) < 1.5
    assert np.all(np.isnan(r.get_distances())) and r.get_distances().shape == (7, 1)
    assert abs(r.get_accelerations()[2, 0] + 9.81) < 0.3
