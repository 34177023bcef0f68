"""How V2's certificates read their arguments: nothing checked up front, each value used where V2 uses it.

V2 checks none of its certificates' arguments; a value is used when a call of at least two robots builds the QP, and
fails there with the Python or numpy error of that use (a ``str`` radius: ``TypeError`` at ``safety_radius**2``;
a list of commands: ``AttributeError`` at ``dxi.shape``), while a value it can compute with (a negative gain, an
``np.int64``, ``True``) is simply used. `V2Arguments.spec` and `v2_positions` reach each value in V2's order, by
the same operations, so a script gets V2's answer or V2's error (``tests/unit/robotarium_exp/rps_contract.json``).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.rps.errors import RobotariumError
from robotarium_exp.rps.utilities.barrier_rows import BarrierSpec, barrier_rows

FloatArray = NDArray[np.float64]

V2_BOUNDARY = (-1.7, 1.7, -1.1, 1.1)
"""V2's default boundary of ``create_si_barrier_certificate_with_boundary`` ([x_min, x_max, y_min, y_max])."""


@dataclass(frozen=True)
class V2Arguments:
    """A V2 certificate's arguments as the script gave them; ``boundary_points`` None without walls."""

    safety_radius: Any
    barrier_gain: Any
    magnitude_limit: Any
    boundary_points: Any = None

    def spec(self) -> BarrierSpec:
        """The QP's numbers, each reached as V2 reaches it when it builds the rows (pairs, walls, speed polygon), so
        a value V2 cannot compute with raises V2's error here."""
        radius, gain, limit, walls = self.safety_radius, self.barrier_gain, self.magnitude_limit, self.boundary_points
        row = np.zeros(6)  # V2 writes each bound into a float array: a str fails there, None becomes NaN
        h = np.float64(0.0) - radius**2
        row[0] = gain * (h**3)
        if walls is not None:
            row[1] = 0.4 * gain * (walls[3] - radius / 2 - 0.0) ** 3
            row[2] = 0.4 * gain * (0.0 - walls[2] - radius / 2) ** 3
            row[3] = 0.4 * gain * (walls[1] - radius / 2 - 0.0) ** 3
            row[4] = 0.4 * gain * (0.0 - walls[0] - radius / 2) ** 3
        else:
            row[5] = limit  # the plain certificate's first side of the speed polygon
        row[5] = limit * np.cos(np.pi / 8)
        bounds = None if walls is None else (float(walls[0]), float(walls[1]), float(walls[2]), float(walls[3]))
        return BarrierSpec(float(radius), float(gain), float(limit), bounds, True, full_first_side=walls is None)


def v2_positions(x: Any, n: int, walls: bool) -> FloatArray:
    """The positions V2's certificate uses for ``n`` robots: the first two rows and the first ``n`` columns of ``x``,
    with V2's error where ``x`` has fewer columns (or is no array), no row, or, with ``walls``, a single row. A
    single row without walls V2 accepts (`one_row_rows`), and so do we, with a warning."""
    positions = x[:2, :]
    if positions.shape[1] < n:
        positions[:, positions.shape[1]]  # V2's loop over the pairs stops here with numpy's IndexError
    if positions.shape[0] == 0:
        np.zeros(2)[:] = -2 * (positions[:, 0] - positions[:, 1])  # V2's first pair row: numpy's ValueError
    if walls and positions.shape[0] < 2:
        positions[1, 0]  # V2's first wall row (after the pairs) reads y: numpy's IndexError
    if positions.shape[0] == 1:
        warnings.warn(
            f"x has one row (shape {np.shape(x)}): as V2, each robot's one value is read as both of its coordinates "
            'in the pair rows; give x as 2xN [x; y] (or 3xN poses).',
            RuntimeWarning,
            stacklevel=3,
        )
    return np.asarray(positions[:, :n], dtype=float)


def one_row_rows(x: FloatArray, spec: BarrierSpec) -> tuple[FloatArray, FloatArray]:
    """V2's plain certificate's rows for positions given as one row (1, N): V2 broadcasts each pair's difference d
    into both coordinates of its row (-2 (d, d)) but its barrier is h = d^2 - R^2; the speed polygon is as ever."""
    a, b = barrier_rows(np.vstack([x[0], x[0]]), spec)
    i, j = np.triu_indices(x.shape[1], k=1)  # the pairs in barrier_rows' order, V2's
    b[: i.size] = spec.barrier_gain * ((x[0, i] - x[0, j]) ** 2 - spec.safety_radius**2) ** 3
    return a, b


def checked_pair(u: object, x: object, u_name: str, x_name: str, state_rows: int = 2) -> tuple[FloatArray, FloatArray]:
    """Classic's certificates' inputs after classic's own checks: two finite arrays, ``u`` 2 x N and ``x``
    ``state_rows`` x N; else our refusal."""
    if not isinstance(u, np.ndarray) or not isinstance(x, np.ndarray):
        msg = f'{u_name} and {x_name} must be numpy arrays; got {type(u).__name__} and {type(x).__name__}.'
        raise RobotariumError(msg)
    if u.ndim != 2 or u.shape[0] != 2 or x.ndim != 2 or x.shape[0] < state_rows or x.shape[1] != u.shape[1]:
        msg = (
            f'{u_name} must be 2xN and {x_name} {state_rows}xN with the same N; got {u_name} {u.shape} and '
            f'{x_name} {x.shape}.'
        )
        raise RobotariumError(msg)
    if not (np.isfinite(u).all() and np.isfinite(x).all()):
        msg = f'{u_name} and {x_name} must be finite.'
        raise RobotariumError(msg)
    return np.asarray(u, dtype=float), np.asarray(x, dtype=float)
