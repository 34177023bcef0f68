"""``rps.utilities.misc`` (V2): start slots, random poses, arrival checks, figure and file helpers.

Random draws come from Python's ``random`` (charger slots) and ``np.random`` (poses), in V2's order, so that a
script's seeds reproduce V2's draws.
"""

from __future__ import annotations

import random
from collections.abc import Callable
from datetime import datetime
from typing import Any

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

CHARGER_SLOTS = 22
"""V2 starts robots on 22 charger slots: 11 positions along x on each of the two long sides, facing the arena."""


def determine_font_size(robotarium_instance: Any, font_height_meters: float) -> float:
    """Font size (points) whose height is ``font_height_meters`` in the Robotarium's figure."""
    figure = robotarium_instance._fig
    figure.canvas.draw()
    height_px = figure.get_size_inches()[1] * figure.dpi
    bounds = robotarium_instance.BOUNDARIES
    return float(height_px * font_height_meters / (bounds[3] - bounds[2]))


def generate_initial_poses(N: int, width: float = 3.0, height: float = 1.0) -> FloatArray:
    """N distinct charger slots as start poses (3xN), drawn with ``random.sample`` as V2 does (and, as V2, a
    ``ValueError`` from it for more robots than the 22 slots).

    The slots: x at 11 points evenly over ``width``, y = -/+ ``height`` / 2, heading into the arena.
    """
    x = np.repeat(np.linspace(-width / 2, width / 2, 11), 2)  # slot order: x-major, bottom then top (V2's)
    y = np.tile([-height / 2, height / 2], 11)
    theta = np.where(y < 0, np.pi / 2, -np.pi / 2)
    picked = random.sample(range(CHARGER_SLOTS), N)
    return np.vstack([x[picked], y[picked], theta[picked]]).reshape(3, -1)


def _random_points(N: int, spacing: float, width: float, height: float, noun: str, fewer: str) -> FloatArray:
    """N random points (2xN) at least ``spacing`` apart in a width x height box centred at the origin, with V2's
    checks and messages (which name the ``noun`` asked for); rejection sampling from ``np.random``, up to 10,000
    candidates, as V2."""
    if not (isinstance(N, int) and N > 0):
        raise AssertionError('N must be a positive integer.')
    if not spacing > 0:
        raise AssertionError('spacing must be positive.')
    if not (width > 0 and height > 0):
        raise AssertionError('width and height must be positive.')
    most = int(np.floor(width * height / spacing**2))
    if N > most:
        msg = (
            f'Cannot fit {N} {noun} with spacing {spacing:.2f} m into a {width:.2f} x {height:.2f} m area. '
            f'Approximate maximum: {most}.'
        )
        raise AssertionError(msg)
    points = np.zeros((2, 0))
    for _ in range(10_000):
        if points.shape[1] == N:
            break
        candidate = (np.random.rand(2) - 0.5) * np.array([width, height])
        if points.shape[1] == 0 or np.hypot(*(points - candidate[:, None])).min() >= spacing:
            points = np.hstack([points, candidate[:, None]])
    if points.shape[1] < N:
        msg = f'Could not place {N} {noun} with spacing {spacing:.2f} m after 10000 attempts. Try reducing {fewer}.'
        raise AssertionError(msg)
    placed = np.zeros((2, N))  # V2 copies the points into a 2xN array (so an N of True fails here, as in V2)
    placed[:] = points
    return placed


def generate_random_positions(N: int, spacing: float = 0.5, width: float = 3.0, height: float = 1.8) -> FloatArray:
    """N random positions (2xN) at least ``spacing`` apart in a width x height box centred at the origin."""
    return _random_points(N, spacing, width, height, 'positions', 'N or spacing')


def generate_random_poses(N: int, spacing: float = 0.5, width: float = 3.0, height: float = 1.8) -> FloatArray:
    """N random poses (3xN): random positions as `generate_random_positions` and headings uniform in
    [-pi, pi)."""
    points = _random_points(N, spacing, width, height, 'poses', 'N or Spacing')
    return np.vstack([points, np.random.rand(N) * 2 * np.pi - np.pi])


def create_at_pose(
    position_error: float = 0.05, rotation_error: float = 0.2
) -> Callable[[FloatArray, FloatArray], tuple[bool, NDArray[np.bool_]]]:
    """``check(states, poses) -> (all arrived, per-robot mask)`` within the position and heading errors."""

    def check(states: FloatArray, poses: FloatArray) -> tuple[bool, NDArray[np.bool_]]:
        _check_columns(states, 3, poses, 3, 'poses')
        heading = np.abs(np.arctan2(np.sin(states[2] - poses[2]), np.cos(states[2] - poses[2])))
        mask = (np.hypot(*(states[:2] - poses[:2])) <= position_error) & (heading <= rotation_error)
        return bool(mask.all()), mask

    return check


def create_at_position(
    position_error: float = 0.05,
) -> Callable[[FloatArray, FloatArray], tuple[bool, NDArray[np.bool_]]]:
    """``check(states, positions) -> (all arrived, per-robot mask)``."""

    def check(states: FloatArray, positions: FloatArray) -> tuple[bool, NDArray[np.bool_]]:
        _check_columns(states, 2, positions, 2, 'positions')
        mask = np.hypot(*(states[:2] - positions[:2])) <= position_error
        return bool(mask.all()), mask

    return check


def _check_columns(states: FloatArray, state_rows: int, goals: FloatArray, goal_rows: int, name: str) -> None:
    """V2's argument checks of the arrival tests, with its messages."""
    n = states.shape[1]
    if state_rows == 3 and states.shape[0] != 3:
        raise AssertionError(f'states must be 3xN. Got {states.shape[0]}x{n}.')
    if states.shape[0] < state_rows:
        raise AssertionError(f'states must be at least 2xN. Got {states.shape[0]}x{n}.')
    if goals.shape[0] != goal_rows:
        raise AssertionError(f'{name} must be {goal_rows}xN. Got {goals.shape[0]}x{goals.shape[1]}.')
    if goals.shape[1] != n:
        raise AssertionError(f'states and {name} must have the same number of columns ({n} vs {goals.shape[1]}).')


def rotation_matrix(theta: Any) -> FloatArray:
    """3 x 3 x N homogeneous planar rotations, one per angle (V2's MATLAB-shaped result)."""
    theta = np.atleast_1d(theta).ravel()
    out = np.zeros((3, 3, theta.size))
    out[0, 0] = out[1, 1] = np.cos(theta)
    out[0, 1], out[1, 0] = -np.sin(theta), np.sin(theta)
    out[2, 2] = 1.0
    return out


def unique_filename(file_name: str) -> str:
    """``file_name`` with the current time appended and ``.npy`` (V2's data-saving helper)."""
    return f'{file_name}_{datetime.now().strftime("%Y_%m_%d_%H_%M_%S")}.npy'
