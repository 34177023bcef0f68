"""rps.utilities names of V2: graph Laplacians, position and pose controllers, random positions, the QP helper."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.rps.utilities.controllers import (
    create_pose_controller_clf,
    create_pose_parking_controller_clf,
    create_uni_position_controller,
)


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


# Outputs of V2's own functions on fixed inputs, recorded by running the official simulator (numbers, not its code):
# the hybrid pose controller over three successive calls (its phases are remembered), and the heading law with
# backwards motion at gain 0.7 and limit 2.0.
V2_HYBRID_GOALS = [
    [0.0, 0.5, -0.5, 0.2, 0.02, 0.0],
    [0.0, 0.3, 0.1, -0.4, 0.01, 0.035],
    [0.0, 1.0, -2.0, 3.0, 0.5, -1.0],
]
V2_HYBRID_STATES = [
    [
        [0.000369046007, 0.589623661253, -0.582241356609, -0.067177551627, -0.116401235552, -0.297493966499],
        [0.018043080779, 0.702064573666, -0.047661955565, -0.586142469946, 0.156952615056, 0.142066102448],
        [0.105414248998, 0.069531955292, -2.029251822463, 3.695303194458, -0.844214547285, -1.45761576104],
    ],
    [
        [-0.076048909592, 0.448418490409, -0.573669401512, 0.190596354757, -0.030697859258, 0.010850574353],
        [0.006270043465, 0.292522762215, -0.000670388433, -0.421547715834, 0.008059962184, 0.03953235944],
        [-1.530135765505, 0.522246723966, -2.978519078057, 2.191162760574, 1.560898623386, -1.807534675332],
    ],
    [
        [-0.000650434099, 0.517687797348, -0.511672008655, 0.197765961008, 0.022209282865, 0.001275635485],
        [-0.024501116528, 0.301522804608, 0.127176468435, -0.430942893563, 0.02718765376, 0.037387080514],
        [-0.641470394107, 3.000416546342, -1.237740287915, 1.800711097895, 0.574516228771, -0.42331041633],
    ],
]
V2_HYBRID_DXU = [
    [
        [0.0, -0.03418257119, -0.119851745983, -0.119819883095, 0.119972017558, 0.05312767462],
        [-0.210828497996, -3.719302468432, 6.183758766735, -6.173591517497, 0.043192229306, 2.224309181907],
    ],
    [
        [0.0, 0.038748470049, -0.071228832731, 0.009652784125, 0.001953381577, 0.0],
        [3.060271531011, -0.756579635276, -4.731226416265, -2.063723760804, -3.045301247969, 1.615069350664],
    ],
    [
        [-0.011311757678, 0.0, 0.023599214474, 0.023695625169, 0.0, 0.0],
        [4.371451667755, -4.000833092685, 0.145222253814, -0.603976974217, -0.149032457543, -1.15337916734],
    ],
]
V2_BACKWARDS_DXI = [
    [-0.018878212535, 0.06829102672, -0.006651732015, 0.066724756083, 0.143852259166, -0.067566225101],
    [0.020313861039, -0.046330757654, 0.012726841123, -0.118719452785, -0.05793015965, -0.01961959728],
]
V2_BACKWARDS_STATES = [
    [0.8987638721, 1.145222007454, -1.323527792484, -0.794642365987, 0.646903422573, -1.992419784174],
    [-0.463169864952, -0.09728692567, 1.257014977287, 0.689403900571, -0.327213420222, -0.3685758941],
    [-2.227640809336, -1.932308849836, 2.688610711245, 0.328777018487, -2.007147848161, 2.413100634736],
]
V2_BACKWARDS_DXU = [
    [-0.003191706882, 0.013427582913, 0.008085534669, 0.017372610885, -0.005806508026, 0.026148400917],
    [1.852106061323, 1.788949627354, -1.034212520946, -1.835729681445, -1.952280926592, 1.473757061828],
]


def test_hybrid_pose_controller_equals_v2_over_successive_calls() -> None:
    from robotarium_exp.rps.utilities.controllers import create_pose_controller_hybrid

    controller = create_pose_controller_hybrid()
    goals = np.array(V2_HYBRID_GOALS)
    for states, expected in zip(V2_HYBRID_STATES, V2_HYBRID_DXU, strict=True):
        np.testing.assert_allclose(controller(np.array(states), goals), expected, atol=1e-9)


def test_hybrid_pose_controller_phases_can_be_kept_by_the_caller() -> None:
    """With ``in_approach_state`` the phases are the caller's: updated in place and returned with the commands."""
    from robotarium_exp.rps.utilities.controllers import create_pose_controller_hybrid

    controller = create_pose_controller_hybrid()
    goals = np.zeros((3, 2))
    states = np.array([[0.01, -0.5], [0.0, 0.0], [1.0, 0.0]])  # robot 0 near but turned: it rotates, leaves approach
    phases = np.ones(2)
    dxu, returned = controller(states, goals, phases)
    assert returned is phases and phases.tolist() == [0.0, 1.0]
    np.testing.assert_allclose(dxu[:, 0], [0.0, -2.0])  # turn in place at twice the heading error
    assert dxu[0, 1] == pytest.approx(0.8 * 0.15)  # approach: the clamped error through the heading law
    states[0, 0] = 0.04  # drifted: outside position_error - epsilon but not in approach any more -> still rotates
    dxu, _ = controller(states, goals, phases)
    assert dxu[0, 0] == 0.0 and phases[0] == 1.0  # farther than position_error: back to approaching next time


def test_backwards_heading_law_equals_v2() -> None:
    from robotarium_exp.rps.utilities.transformations import create_si_to_uni_dynamics_with_backwards_motion

    law = create_si_to_uni_dynamics_with_backwards_motion(linear_velocity_gain=0.7, angular_velocity_limit=2.0)
    got = law(np.array(V2_BACKWARDS_DXI), np.array(V2_BACKWARDS_STATES))
    np.testing.assert_allclose(got, V2_BACKWARDS_DXU, atol=1e-9)
