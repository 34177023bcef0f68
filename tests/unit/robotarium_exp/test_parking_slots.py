"""The parking slots' layout beyond the exit (robotarium_exp.design): lanes and rows 0.3 m apart."""

from __future__ import annotations

import numpy as np

from robotarium_exp.parking_slots import slots_in_lanes


def test_slots_lie_in_lanes_beyond_the_exit_filled_farthest_first() -> None:
    slots = slots_in_lanes(np.array([1.0, 2.0]), np.array([1.0, 0.0]), 7, 5, 0.45)
    assert slots.shape == (2, 7)
    # five lanes across the tangent, centred on the exit line; the first row 0.45 m past the exit
    np.testing.assert_allclose(slots[0, :5], 1.45)
    np.testing.assert_allclose(slots[1, :5], 2.0 + 0.3 * np.array([-2, -1, 0, 1, 2]))
    np.testing.assert_allclose(slots[0, 5:], 1.15)  # the next row 0.3 m nearer
    np.testing.assert_allclose(slots[1, 5:], 2.0 + 0.3 * np.array([-2, -1]))


def test_slots_turn_with_the_tangent_and_keep_their_spacing() -> None:
    angle = 0.7
    tangent = np.array([np.cos(angle), np.sin(angle)])
    slots = slots_in_lanes(np.array([0.0, 0.0]), tangent, 3, 3, 0.45)
    along = tangent @ slots
    np.testing.assert_allclose(along, 0.45)
    np.testing.assert_allclose(np.diff(np.array([-tangent[1], tangent[0]]) @ slots), 0.3)
