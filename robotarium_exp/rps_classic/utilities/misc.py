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

from robotarium_exp.rps.utilities.misc import create_at_pose, create_at_position
from robotarium_exp.rps_classic.utilities.checks import (
    INTEGER,
    NDARRAY,
    POSITIVE,
    Check,
    bound,
    columns,
    enforce,
    rows,
    typed,
)

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


AREA = 'the function generate_initial_conditions'
INITIAL_CONDITIONS = (
    typed('N', 'the number of robots (N) to generate intial conditions for', INTEGER),
    typed('spacing', 'the minimum spacing between robots (spacing)'),
    typed('width', 'the width of the area to place robots randomly (width)'),
    typed('height', 'the height of the area to place robots randomly (width)'),
    bound('N', 'the number of robots to generate initial conditions for (N)', POSITIVE),
    bound('spacing', 'the spacing between robots (spacing)', POSITIVE),
    bound('width', 'the width of the area to initialize robots randomly (width)', POSITIVE),
    bound('height', 'the height of the area to initialize robots randomly (height)', POSITIVE),
)
GRID = (
    Check(
        lambda v: v['columns'] != 0,
        'the space between robots (space) is too large compared to the width of the area robots are randomly '
        'initialized in (width).',
        lambda v: (),
    ),
    Check(
        lambda v: v['rows'] != 0,
        'the space between robots (space) is too large compared to the height of the area robots are randomly '
        'initialized in (height).',
        lambda v: (),
    ),
    Check(
        lambda v: v['columns'] * v['rows'] > v['N'],
        'it is impossible to place %r robots within a %r x %r meter area with a spacing of %r meters.',
        lambda v: (v['N'], v['width'], v['height'], v['spacing']),
    ),
)
"""The checks of ``generate_initial_conditions``: its arguments, then the grid they make."""

STATES = typed('states', 'the robot current state argument (states)', NDARRAY)
POSITION_ERROR = typed('position_error', 'the allowable position error argument (position_error)')
AT_POSE = (
    STATES,
    typed('poses', 'the checked pose argument (poses)', NDARRAY),
    POSITION_ERROR,
    typed('rotation_error', 'the allowable angular error argument (rotation_error)'),
    rows('states', 3, 'the dimension of the state of each robot must be 3 ([x;y;theta])', 'Recieved %r.'),
    rows('poses', 3, 'the dimension of the checked pose of each robot must be 3 ([x;y;theta])', 'Recieved %r.'),
    Check(
        lambda v: v['states'].shape == v['poses'].shape,
        'the robot current state and checked pose inputs must be the same size (3xN, where N is the number of robots '
        'being checked). Recieved a state array of size %r x %r and checked pose array of size %r x %r.',
        lambda v: (v['states'].shape[0], v['states'].shape[1], v['poses'].shape[0], v['poses'].shape[1]),
    ),
)
AT_POSITION = (
    STATES,
    typed('points', 'the desired pose argument (poses)', NDARRAY),
    POSITION_ERROR,
    rows('states', 3, 'the dimension of the state of each robot (states) must be 3', 'Recieved %r.'),
    rows('points', 2, 'the dimension of the checked position for each robot (points) must be 2', 'Recieved %r.'),
    columns(
        'states',
        'points',
        'the number of checked points (points) must match the number of robot states provided (states). Recieved a '
        'state array of size %r x %r and desired pose array of size %r x %r.',
    ),
)


def generate_initial_conditions(N: int, spacing: float = 0.3, width: float = 3, height: float = 1.8) -> FloatArray:
    """N random poses (3xN) on the cells of a grid of pitch ``spacing`` over a width x height box at the origin.

    The classic draw, from numpy's global generator so that ``np.random.seed`` repeats it: N distinct cells out of
    the ``floor(width / spacing) * floor(height / spacing)`` (cell c at column c // rows, row c % rows, counted from
    1, so cell 0 is never used), then one heading per robot, uniform in [-pi, pi).
    """
    values = {'N': N, 'spacing': spacing, 'width': width, 'height': height}
    enforce(f'In {AREA}', INITIAL_CONDITIONS, values)
    columns, rows = int(np.floor(width / spacing)), int(np.floor(height / spacing))
    enforce(f'In {AREA}', GRID, {**values, 'columns': columns, 'rows': rows})
    cells = np.random.choice(columns * rows, N, replace=False) + 1
    column, row = np.divmod(cells, rows)
    headings = np.random.rand(N) * 2 * np.pi - np.pi
    return np.vstack([column * spacing - width / 2, row * spacing - height / 2, headings])


def at_pose(
    states: FloatArray, poses: FloatArray, position_error: float = 0.05, rotation_error: float = 0.2
) -> tuple[NDArray[np.intp], ...]:
    """Indices of the robots within ``position_error`` of their positions and ``rotation_error`` of their headings
    (wrapped), as ``np.nonzero`` gives them."""
    values = {'states': states, 'poses': poses, 'position_error': position_error, 'rotation_error': rotation_error}
    enforce('In the at_pose function', AT_POSE, values)
    return np.nonzero(create_at_pose(position_error, rotation_error)(states, poses)[1])


def at_position(states: FloatArray, points: FloatArray, position_error: float = 0.02) -> tuple[NDArray[np.intp], ...]:
    """Indices of the robots (states 3xN) within ``position_error`` of their points (2xN). Classic's own version
    cannot run (its last check reads an undefined name, a ``NameError`` for every call that gets there); this one
    makes that check as meant, with classic's message, and runs."""
    values = {'states': states, 'points': points, 'position_error': position_error}
    enforce('In the at_position function', AT_POSITION, values)
    return np.nonzero(create_at_position(position_error)(states[:2], points)[1])


def determine_marker_size(robotarium_instance: Any, marker_size_meters: float) -> float:
    """A ``scatter`` marker size (points squared) whose diameter spans ``marker_size_meters`` on the arena figure.

    As classic: the arena's width in display pixels (the data-to-display transform of the point (width, height)),
    times the marker's share of that width, squared because scatter sizes are areas.
    """
    to_pixels = robotarium_instance.axes.transData
    width, height = robotarium_instance.boundaries[2], robotarium_instance.boundaries[3]
    width_pixels = to_pixels.transform(np.array([[width, height]]))[0, 0]
    return float((width_pixels * marker_size_meters / width) ** 2)


def determine_font_size(robotarium_instance: Any, font_height_meters: float) -> float:
    """A font size for text ``font_height_meters`` tall: the axes' height in pixels per metre of arena *width*
    (the classic ratio, kept as classic has it), times the height."""
    bottom, top = robotarium_instance.axes.get_window_extent().get_points()[:, 1]
    return float((top - bottom) / robotarium_instance.boundaries[2] * font_height_meters)
