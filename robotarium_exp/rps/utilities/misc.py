"""``rps.utilities.misc``: start slots, random poses, arrival checks (both generations' names)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.errors import RobotariumError

FloatArray = NDArray[np.float64]

CHARGER_SLOTS = 22
"""V2 starts robots on 22 charger slots: x in linspace(-1.545, 1.545, 11), y = +/-0.945, facing the arena."""


def generate_initial_poses(
    n: int, width: float = 3.0, height: float = 1.0, *, rng: np.random.Generator | None = None
) -> FloatArray:
    """N distinct charger slots as start poses (3xN), chosen at random as V2 does."""
    if n > CHARGER_SLOTS:
        msg = (
            f'the V2 initialization starts robots on {CHARGER_SLOTS} charger slots, but {n} robots were asked; '
            'use skip_initialization=True for larger simulated swarms.'
        )
        raise RobotariumError(msg)
    rng = rng if rng is not None else np.random.default_rng()
    x = np.tile(np.linspace(-1.545, 1.545, 11), 2)
    y = np.repeat([-0.945, 0.945], 11)
    theta = np.repeat([np.pi / 2, -np.pi / 2], 11)
    pick = rng.choice(CHARGER_SLOTS, size=n, replace=False)
    return np.vstack([x[pick], y[pick], theta[pick]])


def _uniform(rng: np.random.Generator | None, size: int) -> FloatArray:
    """Uniform draws in [0, 1): from ``rng``, or from numpy's global generator as the testbed's ``rps`` does (so a
    script's ``np.random.seed`` holds)."""
    return rng.random(size) if rng is not None else np.random.rand(size)


def generate_random_positions(
    n: int, spacing: float = 0.5, width: float = 3.0, height: float = 1.8, *, rng: np.random.Generator | None = None
) -> FloatArray:
    """N random positions (2xN) at least ``spacing`` apart in a width x height box centred at the origin.

    Rejection sampling, up to 10,000 candidates. Raises :class:`RobotariumError` when N cannot fit.
    """
    if not (isinstance(n, int) and not isinstance(n, bool) and n > 0):
        raise RobotariumError('N must be a positive integer.')
    if not spacing > 0:
        raise RobotariumError('spacing must be positive.')
    if not (width > 0 and height > 0):
        raise RobotariumError('width and height must be positive.')
    most = int(np.floor(width * height / spacing**2))
    if n > most:
        msg = (
            f'Cannot fit {n} positions with spacing {spacing:.2f} m into a {width:.2f} x {height:.2f} m area. '
            f'Approximate maximum: {most}.'
        )
        raise RobotariumError(msg)
    points = np.zeros((2, 0))
    for _ in range(10_000):
        if points.shape[1] == n:
            break
        candidate = (_uniform(rng, 2) - 0.5) * np.array([width, height])
        if points.shape[1] == 0 or np.hypot(*(points - candidate[:, None])).min() >= spacing:
            points = np.hstack([points, candidate[:, None]])
    if points.shape[1] < n:
        msg = (
            f'Could not place {n} positions with spacing {spacing:.2f} m after 10000 attempts. '
            'Try reducing N or spacing.'
        )
        raise RobotariumError(msg)
    return points


def generate_random_poses(
    n: int, spacing: float = 0.5, width: float = 3.0, height: float = 1.8, *, rng: np.random.Generator | None = None
) -> FloatArray:
    """N random poses (3xN): :func:`generate_random_positions` and headings uniform in [-pi, pi)."""
    points = generate_random_positions(n, spacing, width, height, rng=rng)
    return np.vstack([points, _uniform(rng, n) * 2 * np.pi - np.pi])


def generate_initial_conditions(
    n: int, spacing: float = 0.3, width: float = 3.0, height: float = 1.8, *, rng: np.random.Generator | None = None
) -> FloatArray:
    """Classic name of :func:`generate_random_poses`."""
    return generate_random_poses(n, spacing, width, height, rng=rng)


def create_at_pose(
    position_error: float = 0.05, rotation_error: float = 0.2
) -> Callable[[FloatArray, FloatArray], tuple[bool, NDArray[np.bool_]]]:
    """V2: ``check(states, poses) -> (all arrived, per-robot mask)`` within the position and heading errors."""

    def check(states: FloatArray, poses: FloatArray) -> tuple[bool, NDArray[np.bool_]]:
        heading = np.abs(np.angle(np.exp(1j * (states[2] - poses[2]))))
        mask = (np.hypot(*(states[:2] - poses[:2])) <= position_error) & (heading <= rotation_error)
        return bool(mask.all()), mask

    return check


def create_at_position(
    position_error: float = 0.05,
) -> Callable[[FloatArray, FloatArray], tuple[bool, NDArray[np.bool_]]]:
    """V2: ``check(states, positions) -> (all arrived, per-robot mask)``."""

    def check(states: FloatArray, positions: FloatArray) -> tuple[bool, NDArray[np.bool_]]:
        mask = np.hypot(*(states[:2] - positions[:2])) <= position_error
        return bool(mask.all()), mask

    return check


def at_pose(
    states: FloatArray, poses: FloatArray, position_error: float = 0.05, rotation_error: float = 0.2
) -> tuple[NDArray[np.intp], ...]:
    """Classic: indices of robots at their poses, as ``np.nonzero``."""
    return np.nonzero(create_at_pose(position_error, rotation_error)(states, poses)[1])


def at_position(states: FloatArray, points: FloatArray, position_error: float = 0.02) -> tuple[NDArray[np.intp], ...]:
    """Classic: indices of robots at their positions (working, unlike the classic original)."""
    return np.nonzero(create_at_position(position_error)(states, points)[1])
