"""Parking beyond the exit: where the arena ends (the Robotarium), robots past the exit drive to the next free slot
and leave the swarm."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

PARKED_WITHIN_M = 0.03
"""A robot is parked when its control point is this close to its slot."""


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
