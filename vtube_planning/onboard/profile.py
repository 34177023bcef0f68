"""The plan as the controller reads it: :class:`PlanProfile`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class PlanProfile:
    """The plan as the controller uses it: slowness w = 1/v and density rho, both linear between grid points.

    Outside [0, L] the end values hold. ``Plan.speed`` and ``Plan.density`` are these functions.
    """

    l_m: FloatArray
    slowness_spm: FloatArray
    density_per_m2: FloatArray

    def speed(self, l_m: ArrayLike) -> FloatArray:
        """v*(l) = 1 / (linear interpolation of w), m/s."""
        speed: FloatArray = 1.0 / np.interp(np.asarray(l_m, dtype=float), self.l_m, self.slowness_spm)
        return speed

    def density(self, l_m: ArrayLike) -> FloatArray:
        """rho*(l), linear interpolation, robots/m^2."""
        density: FloatArray = np.interp(np.asarray(l_m, dtype=float), self.l_m, self.density_per_m2)
        return density
