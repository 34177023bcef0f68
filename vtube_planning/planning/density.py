"""The swarm's density along a virtual tube, as the planner models it (``docs/theory.md`` §1.5, §7 A6-A8, §8.3).

The density of a flying swarm is measured by
[`vtube_planning.onboard.density.swarm_density`][vtube_planning.onboard.density.swarm_density], the one definition that
the controller, the logs and the analysis share: the swarm occupies the part of the tube between the projections of its
last and its front robot, padded by one avoidance radius at both ends so that a line-abreast swarm still has a finite
area (resolution A7), ``S = A(l_front + pad) - A(l_back - pad)`` with the tube's cumulative area A, and ``rho = N / S``.

For planning, a swarm of density rho centred at l occupies ``[l_e, l_s]`` with
``A(l_s) - A(l) = A(l) - A(l_e) = N / (2 rho)``. Advancing it rigidly by ``dl`` (Assumption 3) predicts the density
``rho_f`` of (p7), in one of two readings (A6):

* ``local_width``: the swarm is short against the tube's variation, ``rho_f = rho lambda(l) / lambda(l + dl)``;
* ``rigid_shift``: the whole footprint advances, ``rho_f = N / (A(l_s + dl) - A(l_e + dl))``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from vtube_planning.errors import ParamsError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.onboard import swarm_area
from vtube_planning.params import PREDICTIVE_MODELS

FloatArray = NDArray[np.float64]


def footprint(
    tube: VirtualTube, l_center_m: ArrayLike, rho_per_m2: ArrayLike, n_robots: int
) -> tuple[FloatArray, FloatArray]:
    """Back and front arc lengths ``(l_e, l_s)`` of a swarm of N robots at density rho centred at l (area-wise)."""
    center_area = np.asarray(tube.area(np.atleast_1d(np.asarray(l_center_m, dtype=float))))
    half = 0.5 * n_robots / np.asarray(rho_per_m2, dtype=float)
    back = np.asarray(tube.area_inverse(np.atleast_1d(center_area - half)))
    front = np.asarray(tube.area_inverse(np.atleast_1d(center_area + half)))
    return back, front


def predicted_density(
    tube: VirtualTube, l_m: ArrayLike, rho_per_m2: ArrayLike, n_robots: int, lookahead_m: float, model: str
) -> FloatArray:
    """Density rho_f (robots/m^2) after a rigid advance by ``lookahead_m`` of a swarm at l with density rho.

    Parameters
    ----------
    l_m, rho_per_m2
        Arc lengths of the swarm's centre and its densities, broadcast together.
    model
        ``'local_width'`` or ``'rigid_shift'`` (see the module docstring); ``'none'``: no prediction, rho_f = rho.
    """
    l_m = np.atleast_1d(np.asarray(l_m, dtype=float))
    rho = np.broadcast_to(np.asarray(rho_per_m2, dtype=float), l_m.shape)
    if model == 'local_width':
        local: FloatArray = rho * np.asarray(tube.half_width(l_m)) / np.asarray(tube.half_width(l_m + lookahead_m))
        return local
    if model == 'none':
        same: FloatArray = rho.copy()
        return same
    if model == 'rigid_shift':
        back, front = footprint(tube, l_m, rho, n_robots)
        return n_robots / swarm_area(tube, back + lookahead_m, front + lookahead_m, 0.0)
    msg = f'predictive model must be one of {PREDICTIVE_MODELS}; got {model!r}.'
    raise ParamsError(msg)
