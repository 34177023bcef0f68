"""The unicycle x' = v cos theta, y' = v sin theta, theta' = omega, integrated exactly for constant commands."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from unicycle_mapping.errors import MappingError, as_columns

FloatArray = NDArray[np.float64]


def unicycle_step(poses: ArrayLike, dxu: ArrayLike, dt_s: float) -> FloatArray:
    """Poses (3, N) after ``dt_s`` seconds of constant commands [v; omega] (2, N); headings wrapped to (-pi, pi].

    Exact: along an arc the chord has length v dt sinc(omega dt / 2) and the direction theta + omega dt / 2
    (a straight segment when omega = 0).
    """
    poses = as_columns(poses, 3, 'poses')
    dxu = as_columns(dxu, 2, 'unicycle commands dxu', poses.shape[1])
    if isinstance(dt_s, bool) or not isinstance(dt_s, (int, float)) or not np.isfinite(dt_s):
        msg = f'dt_s must be a finite number; got {dt_s!r}.'
        raise MappingError(msg)
    half = 0.5 * dxu[1] * dt_s
    chord = dxu[0] * dt_s * np.sinc(half / np.pi)
    direction = poses[2] + half
    theta = np.angle(np.exp(1j * (poses[2] + dxu[1] * dt_s)))
    return np.vstack([poses[0] + chord * np.cos(direction), poses[1] + chord * np.sin(direction), theta])
