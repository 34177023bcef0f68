"""Points in the tube's coordinates: what projecting robots onto a tube gives, whichever tube.

The exact :class:`~vtube_planning.geometry.tube.VirtualTube` and the sampled tube of a submission
(:class:`~vtube_planning.onboard.sampled_tube.SampledTube`) both return a :class:`Projection`. Both continue
straight beyond their ends with the end widths, so robots before the entrance or past the exit still have an arc
length (``docs/theory.md`` §1.5).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Projection:
    """Points of the plane in the tube's curvilinear coordinates (arrays over robots, one per column).

    Attributes
    ----------
    l_m
        Arc length of the closest centre-line point, (N,). Below 0 or above L for points before the entrance or
        past the exit (projected onto the straight extensions).
    y_m
        Signed lateral offset along the left normal, (N,).
    foot_m
        Closest centre-line point gamma(l), (2, N).
    tangent, normal
        Unit tangent t and left normal n at the foot, (2, N) each.
    half_width_m
        lambda(l) at the foot, (N,).
    length_m
        The tube's length L.
    curvature_per_m
        Signed curvature kappa(l) of the centre line at the foot, (N,) (0 on the straight extensions); with the foot
        and the tangent, the frame a warm start of the next projection begins with.
    """

    l_m: FloatArray
    y_m: FloatArray
    foot_m: FloatArray
    tangent: FloatArray
    normal: FloatArray
    half_width_m: FloatArray
    length_m: float
    curvature_per_m: FloatArray

    @property
    def clearance_m(self) -> FloatArray:
        """Distance to the boundary measured across the tube, ``lambda(l) - |y|`` (negative outside), (N,)."""
        return self.half_width_m - np.abs(self.y_m)

    @property
    def inside(self) -> NDArray[np.bool_]:
        """True where the point lies in the tube: ``0 <= l <= L`` and ``|y| <= lambda(l)``, (N,)."""
        return (self.l_m >= 0.0) & (self.l_m <= self.length_m) & (self.clearance_m >= 0.0)
