"""Classic ``rps.utilities.misc``: random start poses on a grid, arrival checks, marker and font sizing.

Classic example scripts do ``from rps.utilities.misc import *`` and then use ``plt``: the classic module imports
``matplotlib.pyplot as plt`` (and ``numpy as np``) at its top, so a star import hands both to the script. This module
does the same on purpose.
"""

from __future__ import annotations

from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from numpy.typing import NDArray

from robotarium_exp.rps.errors import RobotariumError
from robotarium_exp.rps.utilities.misc import create_at_pose, create_at_position

__all__ = [
    'at_pose',
    'at_position',
    'determine_font_size',
    'determine_marker_size',
    'generate_initial_conditions',
    'np',
    'plt',
]

FloatArray = NDArray[np.float64]


def _require(condition: bool, message: str) -> None:
    if not condition:
        raise RobotariumError(message)


def generate_initial_conditions(N: int, spacing: float = 0.3, width: float = 3, height: float = 1.8) -> FloatArray:
    """N random poses (3xN) on the cells of a grid of pitch ``spacing`` over a width x height box at the origin.

    The classic draw, from numpy's global generator so that ``np.random.seed`` repeats it: N distinct cells out of
    the ``floor(width / spacing) * floor(height / spacing)`` (cell c at column c // rows, row c % rows, counted from
    1, so cell 0 is never used), then one heading per robot, uniform in [-pi, pi).
    """
    _require(
        isinstance(N, int),
        f'In the function generate_initial_conditions, the number of robots (N) to generate intial conditions for '
        f'must be an integer. Recieved type {type(N).__name__!r}.',
    )
    _require(
        N > 0,
        f'In the function generate_initial_conditions, the number of robots to generate initial '
        f'conditions for (N) must be positive. Recieved {N!r}.',
    )
    _require(
        spacing > 0,
        f'In the function generate_initial_conditions, the spacing between robots (spacing) must '
        f'be positive. Recieved {spacing!r}.',
    )
    _require(
        width > 0 and height > 0,
        'In the function generate_initial_conditions, the width and height of the '
        f'area must be positive. Recieved {width!r} and {height!r}.',
    )
    columns, rows = int(np.floor(width / spacing)), int(np.floor(height / spacing))
    _require(
        columns * rows > N,
        f'In the function generate_initial_conditions, it is impossible to place {N!r} robots within a {width!r} x '
        f'{height!r} meter area with a spacing of {spacing!r} meters.',
    )
    cells = np.random.choice(columns * rows, N, replace=False) + 1
    column, row = np.divmod(cells, rows)
    headings = np.random.rand(N) * 2 * np.pi - np.pi
    return np.vstack([column * spacing - width / 2, row * spacing - height / 2, headings])


def at_pose(
    states: FloatArray, poses: FloatArray, position_error: float = 0.05, rotation_error: float = 0.2
) -> tuple[NDArray[np.intp], ...]:
    """Indices of the robots within ``position_error`` of their positions and ``rotation_error`` of their headings
    (wrapped), as ``np.nonzero`` gives them (V2's check)."""
    return np.nonzero(create_at_pose(position_error, rotation_error)(states, poses)[1])


def at_position(states: FloatArray, points: FloatArray, position_error: float = 0.02) -> tuple[NDArray[np.intp], ...]:
    """Indices of the robots (states 3xN) within ``position_error`` of their points (2xN). Classic's own version
    cannot run (it checks the shape of an undefined name); this one does."""
    return np.nonzero(create_at_position(position_error)(states[:2], points)[1])


def determine_marker_size(robotarium_instance: Any, marker_size_meters: float) -> float:
    """A ``scatter`` marker size (points squared) whose diameter spans ``marker_size_meters`` on the arena figure.

    As classic: the arena's width in display pixels (the data-to-display transform of the point (width, height)),
    times the marker's share of that width, squared because scatter sizes are areas.
    """
    width, height = robotarium_instance.boundaries[2], robotarium_instance.boundaries[3]
    width_pixels = robotarium_instance.axes.transData.transform(np.array([[width, height]]))[0, 0]
    return float((width_pixels * marker_size_meters / width) ** 2)


def determine_font_size(robotarium_instance: Any, font_height_meters: float) -> float:
    """A font size for text ``font_height_meters`` tall: the axes' height in pixels per metre of arena *width*
    (the classic ratio, kept as classic has it), times the height."""
    bottom, top = robotarium_instance.axes.get_window_extent().get_points()[:, 1]
    return float((top - bottom) / robotarium_instance.boundaries[2] * font_height_meters)
