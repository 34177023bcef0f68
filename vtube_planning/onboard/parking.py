"""Parking beyond the exit: where the arena ends (the Robotarium), robots past the exit drive to the next free slot
and leave the swarm."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

PARKED_WITHIN_M = 0.03
"""A robot is parked when its control point is this close to its slot."""


def parking_slots(end_m: ArrayLike, tangent: ArrayLike, n_robots: int, spacing_m: float = 0.25) -> FloatArray:
    """Slots (2, N) beyond the exit ``end_m`` (2,), in lanes ``spacing_m`` apart, filled farthest first."""
    end, tangent = np.asarray(end_m, dtype=float), np.asarray(tangent, dtype=float)
    normal = np.array([-tangent[1], tangent[0]])
    lanes = max(1, min(n_robots, 5))
    slots = []
    for k in range(n_robots):
        depth, lane = divmod(k, lanes)
        slots.append(end + (0.45 - spacing_m * depth) * tangent + (lane - 0.5 * (lanes - 1)) * spacing_m * normal)
    columns: FloatArray = np.array(slots).T.reshape(2, n_robots)
    return columns


class Parking:
    """The slots (2, N) and which robot holds which (``slot_of``, -1: none yet), kept from period to period."""

    def __init__(self, slots: FloatArray, n_robots: int) -> None:
        self.slots = slots
        self.slot_of = np.full(n_robots, -1)

    def take(self, exited: BoolArray) -> BoolArray:
        """Robots past the exit without a slot take the next free ones, in robot order; returns the parked robots."""
        for k in np.flatnonzero(exited & (self.slot_of < 0)):
            self.slot_of[k] = int((self.slot_of >= 0).sum())
        return self.slot_of >= 0

    def drive(
        self, points: FloatArray, parked: BoolArray, velocity: FloatArray, v_max_mps: float
    ) -> tuple[FloatArray, bool]:
        """Parked robots drive to their slots at up to v_max; done when every robot is in its slot."""
        slots = self.slots
        to_slot = slots[:, self.slot_of[parked]] - points[:, parked]
        reach = np.maximum(np.hypot(to_slot[0], to_slot[1]), 1e-9)
        velocity = velocity.copy()
        velocity[:, parked] = to_slot * np.minimum(1.0, v_max_mps / reach)
        done = bool(parked.all()) and bool(np.all(np.hypot(*(slots[:, self.slot_of] - points)) < PARKED_WITHIN_M))
        return velocity, done
