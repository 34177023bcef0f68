"""Parking beyond the exit: the slots' layout, who takes which slot, driving there."""

from __future__ import annotations

import numpy as np

from robotarium_exp.design import slots_in_lanes
from vtube_planning.onboard.parking import PARKED_WITHIN_M, Parking


def test_robots_past_the_exit_take_the_next_free_slots_in_robot_order() -> None:
    parking = Parking(slots_in_lanes(np.array([0.0, 0.0]), np.array([1.0, 0.0]), 4, 4, 0.45), 4)
    parked = parking.take(np.array([False, True, False, True]))
    assert parked.tolist() == [False, True, False, True] and parking.slot_of.tolist() == [-1, 0, -1, 1]
    parked = parking.take(np.array([True, True, False, False]))  # robot 1 keeps its slot
    assert parking.slot_of.tolist() == [2, 0, -1, 1] and parked.tolist() == [True, True, False, True]


def test_parked_robots_drive_to_their_slots_at_most_at_v_max() -> None:
    slots = np.array([[1.0, 2.0], [0.0, 0.0]])
    parking = Parking(slots, 2)
    parking.take(np.array([True, True]))
    points = np.array([[0.0, 2.0 - 0.5 * PARKED_WITHIN_M], [0.0, 0.0]])
    velocity, done = parking.drive(points, np.array([True, True]), np.zeros((2, 2)), v_max_mps=0.2)
    np.testing.assert_allclose(velocity[:, 0], [0.2, 0.0])  # 1 m away: capped at v_max towards the slot
    np.testing.assert_allclose(velocity[:, 1], [0.5 * PARKED_WITHIN_M, 0.0])  # near: the remaining offset
    assert not done
    _, done = parking.drive(slots + 0.5 * PARKED_WITHIN_M / np.sqrt(2), np.array([True, True]), np.zeros((2, 2)), 0.2)
    assert done


def test_robots_not_parked_keep_their_commands_and_hold_up_done() -> None:
    parking = Parking(np.array([[1.0, 2.0], [0.0, 0.0]]), 2)
    parked = parking.take(np.array([True, False]))
    command = np.array([[0.3, 0.4], [0.1, -0.1]])
    velocity, done = parking.drive(np.array([[1.0, 0.0], [0.0, 0.0]]), parked, command, 0.2)
    np.testing.assert_allclose(velocity[:, 1], command[:, 1])
    assert not done
    np.testing.assert_allclose(velocity[:, 0], 0.0, atol=1e-12)
