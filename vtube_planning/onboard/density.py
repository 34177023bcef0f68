"""The swarm's density, the one definition (``docs/theory.md`` A7-A8): rho = N / S, S the tube's area between the
last and the front robot padded at both ends; the simulator, the experiment, the submission, the planner's
prediction and the analysis of recordings all measure it here."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from vtube_planning.onboard.tube import StepTube

FloatArray = NDArray[np.float64]


def swarm_area(tube: StepTube, l_back_m: ArrayLike, l_front_m: ArrayLike, pad_m: float) -> FloatArray:
    """Area (m^2) of the tube between ``l_back - pad`` and ``l_front + pad``, element-wise (``tube.area``: A(l))."""
    front = np.asarray(l_front_m, dtype=float) + pad_m
    back = np.asarray(l_back_m, dtype=float) - pad_m
    if front.shape != back.shape:
        front, back = np.broadcast_arrays(front, back)
    ends = np.array([front, back]).reshape(2, -1)  # (2, k); scalars as k = 1
    area = np.asarray(tube.area(ends.ravel()), dtype=float).reshape(2, -1)  # one call: the step makes it each period
    between: FloatArray = area[0] - area[1]
    return between


def swarm_density(tube: StepTube, l_m: ArrayLike, pad_m: float) -> float:
    """The swarm's density rho = N / S, robots/m^2: S is the tube's area between the last and the front robot's
    arc lengths ``l_m`` (N,), padded by ``pad_m`` (the initial r_a) at both ends so that a line-abreast swarm has
    a finite density (A7); one number for the whole swarm (A8).
    """
    l_m = np.asarray(l_m, dtype=float)
    if l_m.size == 0:
        msg = 'the swarm density needs at least one robot; got no arc lengths.'
        raise ValueError(msg)
    return float(l_m.size / swarm_area(tube, l_m.min(), l_m.max(), pad_m)[0])
