"""The near-identity diffeomorphism of Olfati-Saber (ACC 2002) between unicycles and single integrators.

The control point of a unicycle at [x; y; theta] is p = [x; y] + d e_theta with e_theta = [cos theta; sin theta]
(``docs/theory.md`` §5, ``docs/robotarium.md`` §8.4). Its velocity is p' = R(theta) diag(1, d) [v; omega], invertible for
d > 0: a desired single-integrator velocity u of the control point is realised exactly by

    v = e_theta . u,        omega = e_theta_perp . u / d.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from unicycle_mapping.errors import MappingError, as_columns, positive

FloatArray = NDArray[np.float64]


def _frame(poses: FloatArray) -> tuple[FloatArray, FloatArray]:
    return np.cos(poses[2]), np.sin(poses[2])


def si_to_uni(dxi: ArrayLike, poses: ArrayLike, d: float, *, finite: bool = True) -> FloatArray:
    """Unicycle commands [v; omega] (2, N) that move the control points at ``dxi`` (2, N), for poses (3, N).

    ``finite=False`` lets NaN and inf through (they propagate as through the Robotarium's own maps)."""
    d = positive(d, 'projection distance d')
    poses = as_columns(poses, 3, 'poses', finite=finite)
    dxi = as_columns(dxi, 2, 'single-integrator velocities dxi', poses.shape[1], finite=finite)
    c, s = _frame(poses)
    return np.vstack([c * dxi[0] + s * dxi[1], (-s * dxi[0] + c * dxi[1]) / d])


def uni_to_si(dxu: ArrayLike, poses: ArrayLike, d: float, *, finite: bool = True) -> FloatArray:
    """Velocities (2, N) of the control points under unicycle commands ``dxu`` [v; omega] (2, N): the inverse map
    (``finite`` as in `si_to_uni`)."""
    d = positive(d, 'projection distance d')
    poses = as_columns(poses, 3, 'poses', finite=finite)
    dxu = as_columns(dxu, 2, 'unicycle commands dxu', poses.shape[1], finite=finite)
    c, s = _frame(poses)
    return np.vstack([c * dxu[0] - d * s * dxu[1], s * dxu[0] + d * c * dxu[1]])


def uni_to_si_states(poses: ArrayLike, d: float, *, finite: bool = True) -> FloatArray:
    """Control points p = [x; y] + d e_theta, (2, N) (``finite`` as in `si_to_uni`)."""
    d = positive(d, 'projection distance d')
    poses = as_columns(poses, 3, 'poses', finite=finite)
    c, s = _frame(poses)
    return np.vstack([poses[0] + d * c, poses[1] + d * s])


def si_to_uni_states(points: ArrayLike, headings: ArrayLike, d: float) -> FloatArray:
    """Poses (3, N) whose control points are ``points`` (2, N) at ``headings`` (N,): the inverse state map."""
    d = positive(d, 'projection distance d')
    points = as_columns(points, 2, 'points')
    headings = np.asarray(headings, dtype=float)
    if headings.shape != (points.shape[1],) or not np.all(np.isfinite(headings)):
        msg = f'headings must be finite with shape ({points.shape[1]},); got {headings.shape}.'
        raise MappingError(msg)
    return np.vstack([points[0] - d * np.cos(headings), points[1] - d * np.sin(headings), headings])


def si_to_uni_constrained(
    dxi: ArrayLike, poses: ArrayLike, d: float, *, v_min: float, v_max: float, a_n: float
) -> tuple[FloatArray, NDArray[np.bool_]]:
    """The map for robots that cannot stop: v in [v_min, v_max], |omega| <= a_n / v (``docs/theory.md`` §5).

    The forward speed is clipped into [v_min, v_max] and the turn rate to the normal-acceleration limit. A command
    that points behind the robot is not reversed: the robot keeps v_min and turns at its largest rate towards it
    (it loiters), to the left when the command points straight back.

    Returns
    -------
    dxu
        Commands [v; omega], (2, N).
    exact
        True where the command was realised exactly (no limit active), (N,).
    """
    v_min, v_max, a_n = positive(v_min, 'v_min'), positive(v_max, 'v_max'), positive(a_n, 'a_n')
    if v_min > v_max:
        msg = f'v_min ({v_min}) exceeds v_max ({v_max}).'
        raise MappingError(msg)
    ideal = si_to_uni(dxi, poses, d)
    v = np.clip(ideal[0], v_min, v_max)
    turn_limit = a_n / v
    behind = ideal[0] < 0.0
    toward = np.where(ideal[1] < 0.0, -1.0, 1.0)
    omega = np.where(behind, toward * turn_limit, np.clip(ideal[1], -turn_limit, turn_limit))
    exact = (v == ideal[0]) & (omega == ideal[1])
    return np.vstack([v, omega]), exact
