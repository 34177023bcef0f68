"""What the swarm step needs of a tube: a :class:`StepTube`.

The exact :class:`~vtube_planning.geometry.tube.VirtualTube` and the sampled tube a submission carries
(:class:`~vtube_planning.onboard.sampled_tube.SampledTube`) both are one.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from vtube_planning.onboard.projection import Projection

FloatArray = NDArray[np.float64]


class StepTube(Protocol):
    """A tube the swarm step can fly: its length, projections of robots onto it, and its cumulative area."""

    @property
    def length_m(self) -> float:
        """The tube's length L, m."""
        ...

    def project(self, points_m: ArrayLike) -> Projection:
        """Every column of (2, N) points in the tube's coordinates."""
        ...

    def project_near(self, points_m: ArrayLike, near: Projection) -> Projection:
        """:meth:`project`, which may start from ``near``, a projection of N points close to these."""
        ...

    def half_width_slope(self, l_m: ArrayLike) -> FloatArray | float:
        """d lambda / dl, 0 beyond both ends (the Robotarium flight's wall rows: a narrowing closes in on a robot
        that flies on)."""
        ...

    def area(self, l_m: ArrayLike) -> FloatArray | float:
        """Cumulative area A(l), m^2, continued straight with the end widths beyond both ends."""
        ...
