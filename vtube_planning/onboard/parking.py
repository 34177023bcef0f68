"""Parking beyond the exit: where the arena ends (the Robotarium), robots past the exit drive to a free slot and
leave the swarm.

A robot that leaves takes a free slot of the farthest row that has one (robots bound for a far row do not have to
pass parked ones), on its own side of the tube's axis where it can, the outermost there: slots in front of the
exit fill last, and robots do not cross each other's way. Taken in a fixed order across the row, two robots leaving
side by side swapped sides and stalled face to face (the trapezoid, four robots without initialization); taken
in order across, the last robots met parked ones in front of the exit.

Robots on their way trade the slots they hold where that shortens their ways in sum (an assignment of least total
distance, whose straight ways do not cross): robots that left the tube in an order unlike their slots' (one
overshooting towards the arena's edge) otherwise held each other off their slots to the end, two with swapped
slots face to face and a third between them bound for the slot they screened (the curve's twenty-robot tube flown
with six robots, V2's initialization seed 1: ``docs/sweep``). Robots in their slots keep them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

PARKED_WITHIN_M = 0.03
"""A robot is parked when its control point is this close to its slot."""
ROW_M = 1e-6
"""Slots whose depths beyond the exit differ by less than this form a row."""
TRADE_M = 0.01
"""Robots trade slots when that shortens their ways by more than this in sum (no trading back and forth over
rounding)."""


class Parking:
    """The slots (2, N), each one's depth beyond the exit and lateral offset from the tube's axis (``depth_m``,
    ``offset_m``, (N,)), and which robot holds which (``slot_of``, -1: none yet), kept from period to period."""

    def __init__(self, slots: FloatArray, n_robots: int, depth_m: FloatArray, offset_m: FloatArray) -> None:
        self.slots = slots
        self.depth_m, self.offset_m = np.asarray(depth_m, dtype=float), np.asarray(offset_m, dtype=float)
        self.slot_of = np.full(n_robots, -1)

    def take(self, exited: BoolArray, offset_m: FloatArray) -> BoolArray:
        """Robots past the exit without a slot, in robot order, take one (module doc); ``offset_m`` (N,): the
        robots' lateral offsets. Returns the robots that hold a slot."""
        for k in np.flatnonzero(exited & (self.slot_of < 0)):
            free = np.setdiff1d(np.arange(self.depth_m.size), self.slot_of)
            row = free[self.depth_m[free] > self.depth_m[free].max() - ROW_M]
            side = row[self.offset_m[row] * offset_m[k] >= 0.0]
            if side.size:
                self.slot_of[k] = side[np.argmax(np.abs(self.offset_m[side]))]
            else:
                self.slot_of[k] = row[np.argmin(np.abs(self.offset_m[row] - offset_m[k]))]
        return self.slot_of >= 0

    def drive(self, points: FloatArray, parked: BoolArray, velocity: FloatArray, v_max_mps: float) -> FloatArray:
        """Parked robots drive to their slots at up to v_max, trading slots on the way (module doc); the others keep
        their ``velocity``."""
        self._trade(points, parked)
        to_slot = self.slots[:, self.slot_of[parked]] - points[:, parked]
        reach = np.maximum(np.hypot(to_slot[0], to_slot[1]), 1e-9)
        velocity = velocity.copy()
        velocity[:, parked] = to_slot * np.minimum(1.0, v_max_mps / reach)
        return velocity

    def _trade(self, points: FloatArray, parked: BoolArray) -> None:
        """The slots held by parked robots not yet in them go to those robots by least total distance, if that
        shortens their ways by more than :data:`TRADE_M`."""
        robots = np.flatnonzero(parked)
        held = self.slot_of[robots]
        gaps = np.hypot(*(self.slots[:, None, held] - points[:, robots, None]))  # (robots, their slots)
        away = np.diagonal(gaps) >= PARKED_WITHIN_M
        if np.count_nonzero(away) < 2:
            return
        gaps = gaps[np.ix_(away, away)]
        rows, cols = linear_sum_assignment(gaps)
        if gaps[rows, cols].sum() < np.trace(gaps) - TRADE_M:
            self.slot_of[robots[away][rows]] = held[away][cols]

    def all_in(self, points: FloatArray, parked: BoolArray) -> bool:
        """Done: every robot holds a slot and its control point (``points``, (2, N)) is within
        :data:`PARKED_WITHIN_M` of it."""
        near = np.hypot(*(self.slots[:, self.slot_of] - points)) < PARKED_WITHIN_M
        return bool(parked.all()) and bool(near.all())
