"""Parking beyond the exit: which robot takes which slot (the farthest row first, on its own side, the outermost
there), driving there, trading slots on the way."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from vtube_planning.onboard.parking import PARKED_WITHIN_M, TRADE_M, Parking

# two rows (0.6 and 0.3 m beyond an exit at x = 0 facing +x) of four lanes, 0.3 m apart across y = 0
OFFSETS = np.array([-0.45, -0.15, 0.15, 0.45])
SLOTS = np.array([[0.6] * 4 + [0.3] * 4, [*OFFSETS, *OFFSETS]])


def lanes() -> Parking:
    return Parking(SLOTS, 8, SLOTS[0], SLOTS[1])


def test_robots_take_the_farthest_row_on_their_side_outermost_first() -> None:
    parking = lanes()
    y = np.array([0.1, -0.1, 0.05, 0.2, -0.2, 0.0, 0.0, 0.0])
    parked = parking.take(np.array([True, True, False, False, False, False, False, False]), y)
    assert parked.tolist() == [True, True] + [False] * 6
    assert parking.slot_of[:2].tolist() == [3, 0]  # robot 0 left of the axis: +0.45; robot 1 right: -0.45
    parking.take(np.array([True, True, True, True, False, False, False, False]), y)
    assert parking.slot_of[:4].tolist() == [3, 0, 2, 1]  # robot 2 (left): +0.15; robot 3 (left, none left): nearest
    parking.take(np.array([True] * 5 + [False] * 3), y)
    assert parking.slot_of[4] == 4  # the far row is full: the near row, right of the axis, outermost


def test_a_robot_on_the_axis_takes_either_side_and_robots_keep_their_slots() -> None:
    parking = lanes()
    parking.take(np.array([True] + [False] * 7), np.zeros(8))
    assert parking.slot_of[0] in (0, 3)
    first = parking.slot_of[0]
    parking.take(np.array([True] * 8), np.zeros(8))  # robot 0 keeps its slot; every slot is taken once
    assert parking.slot_of[0] == first and sorted(parking.slot_of.tolist()) == list(range(8))
    assert set(parking.slot_of[:4].tolist()) == {0, 1, 2, 3}  # the first four fill the far row


def test_parked_robots_drive_to_their_slots_at_most_at_v_max() -> None:
    slots = np.array([[1.0, 2.0], [0.0, 0.0]])
    parking = Parking(slots, 2, np.array([1.0, 2.0]), np.zeros(2))
    parking.take(np.array([True, True]), np.zeros(2))
    assert parking.slot_of.tolist() == [1, 0]  # the farthest row first
    points = np.array([[0.0, 1.0 - 0.5 * PARKED_WITHIN_M], [0.0, 0.0]])
    velocity = parking.drive(points, np.array([True, True]), np.zeros((2, 2)), v_max_mps=0.2)
    np.testing.assert_allclose(velocity[:, 0], [0.2, 0.0])  # 2 m away: capped at v_max towards the slot
    np.testing.assert_allclose(velocity[:, 1], [0.5 * PARKED_WITHIN_M, 0.0])  # near: the remaining offset
    assert not parking.all_in(points, np.array([True, True]))
    at = slots[:, parking.slot_of] + 0.5 * PARKED_WITHIN_M / np.sqrt(2)
    assert parking.all_in(at, np.array([True, True]))


def test_robots_not_parked_keep_their_commands_and_hold_up_done() -> None:
    parking = Parking(np.array([[1.0, 2.0], [0.0, 0.0]]), 2, np.array([1.0, 2.0]), np.zeros(2))
    parked = parking.take(np.array([True, False]), np.zeros(2))
    command = np.array([[0.3, 0.4], [0.1, -0.1]])
    velocity = parking.drive(np.array([[2.0, 0.0], [0.0, 0.0]]), parked, command, 0.2)
    np.testing.assert_allclose(velocity[:, 1], command[:, 1])
    assert parking.slot_of.tolist() == [1, -1]
    assert not parking.all_in(np.array([[2.0, 2.0], [0.0, 0.0]]), parked)  # robot 0 in its slot; 1 holds none
    np.testing.assert_allclose(velocity[:, 0], 0.0, atol=1e-12)


def test_robots_with_swapped_slots_trade_them() -> None:
    """The sweep's deadlock (module doc): two robots beyond a row of slots, each bound for the slot beyond the
    other, and one between them bound for the slot they screen; the outer two trade, the middle one keeps its own."""
    slots = np.array([[1.4, 1.4, 1.4], [-0.725, -0.425, -0.125]])
    parking = Parking(slots, 3, np.zeros(3), slots[1])
    parking.slot_of[:] = [2, 0, 1]
    points = np.array([[1.488, 1.488, 1.299], [-0.535, -0.318, -0.425]])
    velocity = parking.drive(points, np.ones(3, dtype=bool), np.zeros((2, 3)), v_max_mps=0.2)
    assert parking.slot_of.tolist() == [0, 2, 1]
    assert velocity[1, 0] < 0.0 < velocity[1, 1]  # the outer two now move apart, opening the way


def total(slots: np.ndarray, points: np.ndarray, assignment: np.ndarray) -> float:
    """The robots' ways to their slots (``assignment``: each robot's slot), summed."""
    return float(np.hypot(*(slots[:, assignment] - points)).sum())


def test_trades_reach_the_least_total_distance_and_spare_robots_in_their_slots() -> None:
    """Random slots and robots against every permutation of the slots held by robots on their way (the oracle);
    robots already in their slots keep them; a trade that saves less than TRADE_M is not made."""
    rng = np.random.default_rng(7)
    for _ in range(60):
        n = int(rng.integers(2, 6))
        slots = rng.uniform(-1.0, 1.0, (2, n))
        parking = Parking(slots, n, np.zeros(n), np.zeros(n))
        parking.slot_of[:] = rng.permutation(n)
        points = rng.uniform(-1.0, 1.0, (2, n))
        settled = rng.random(n) < 0.3
        points[:, settled] = slots[:, parking.slot_of[settled]] + 0.3 * PARKED_WITHIN_M
        before = parking.slot_of.copy()
        parking.drive(points, np.ones(n, dtype=bool), np.zeros((2, n)), v_max_mps=0.2)
        assert np.array_equal(parking.slot_of[settled], before[settled])
        assert sorted(parking.slot_of.tolist()) == list(range(n))

        away = np.flatnonzero(~settled)
        best = before.copy()
        for order in itertools.permutations(before[away]):
            candidate = before.copy()
            candidate[away] = order
            best = candidate if total(slots, points, candidate) < total(slots, points, best) else best
        if total(slots, points, best) < total(slots, points, before) - TRADE_M:
            assert total(slots, points, parking.slot_of) == pytest.approx(total(slots, points, best), abs=1e-9)
        else:
            assert np.array_equal(parking.slot_of, before)
