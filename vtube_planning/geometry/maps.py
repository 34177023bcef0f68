"""Seeded random obstacle maps with a passage to find: the families a study draws its environments from.

Every family makes an 80 m x 40 m map (the paper's scale: 60 m tubes, Table 1's swarm) with the start at the
middle of its left edge and the goal at the middle of its right edge, 2 m in, and the tube limits of the paper's
scenes (half-width 1.2 to 4.5 m, 0.3 m kept from the obstacles, turns no tighter than v_min^2 / a_n = 4 m):

- ``forest``: ``clutter`` discs (radius 0.8-2.5 m, at least 1 m apart), none within 6 m of the start or goal;
- ``blocks``: ``clutter`` rectangles (1-6 m by 1-6 m, any orientation), the same exclusions;
- ``bottleneck``: a wall across the map at a random x in [30, 50] m with one opening of full width ``width_m`` at
  a random height, and ``clutter`` discs on either side.

:func:`random_map` draws one map of a family from its seed (numpy's ``default_rng``): the same family, seed and
difficulty give the same map on every machine.
"""

from __future__ import annotations

import math

import numpy as np

from vtube_planning.geometry.generate import TubeSpec
from vtube_planning.geometry.obstacles import Disc, Obstacles, Polygon
from vtube_planning.geometry.workspace import Workspace

FAMILIES = ('forest', 'blocks', 'bottleneck')
SIZE_M = (80.0, 40.0)
START_M, GOAL_M = (2.0, 20.0), (78.0, 20.0)
CLEAR_OF_ENDS_M = 6.0
"""No obstacle within this distance of the start or the goal."""
LIMITS = {'half_width_min_m': 1.2, 'half_width_max_m': 4.5, 'margin_m': 0.3, 'turn_radius_min_m': 4.0}
"""The tube's limits: the paper's narrowest and widest half-width (scenes A-D), Table 1's v_min^2 / a_n."""


def random_map(family: str, seed: int, *, clutter: int = 30, width_m: float = 4.0) -> TubeSpec:
    """The map of ``family`` (module doc) drawn from ``seed``, with ``clutter`` obstacles and, for ``bottleneck``,
    an opening ``width_m`` wide; a ValueError names an unknown family."""
    rng = np.random.default_rng(seed)
    if family == 'forest':
        obstacles = Obstacles(_discs(rng, clutter, (8.0, 72.0)))
    elif family == 'blocks':
        obstacles = Obstacles(polygons=_blocks(rng, clutter))
    elif family == 'bottleneck':
        x = float(rng.uniform(30.0, 50.0))
        y = float(rng.uniform(8.0, 32.0 - width_m))
        wall = (
            Polygon(((x, 0.0), (x + 2.0, 0.0), (x + 2.0, y), (x, y))),
            Polygon(((x, y + width_m), (x + 2.0, y + width_m), (x + 2.0, 40.0), (x, 40.0))),
        )
        discs = _discs(rng, clutter, (8.0, 72.0), keep_out=(x - 3.0, x + 5.0))
        obstacles = Obstacles(discs, wall)
    else:
        msg = f'unknown map family {family!r}; choose one of {FAMILIES}.'
        raise ValueError(msg)
    bounds = Workspace(0.0, SIZE_M[0], 0.0, SIZE_M[1], margin_m=0.5)
    return TubeSpec(bounds, obstacles, START_M, GOAL_M, **LIMITS)


def _clear_of_ends(x: float, y: float, reach: float) -> bool:
    return all(math.hypot(x - ex, y - ey) > reach + CLEAR_OF_ENDS_M for ex, ey in (START_M, GOAL_M))


def _discs(
    rng: np.random.Generator, count: int, x_range: tuple[float, float], keep_out: tuple[float, float] | None = None
) -> tuple[Disc, ...]:
    """``count`` discs at least 1 m apart, clear of the ends (and of ``keep_out``, an x interval)."""
    discs: list[Disc] = []
    for _ in range(100 * count):
        if len(discs) == count:
            break
        x, y, r = float(rng.uniform(*x_range)), float(rng.uniform(2.0, 38.0)), float(rng.uniform(0.8, 2.5))
        if keep_out is not None and keep_out[0] - r < x < keep_out[1] + r:
            continue
        apart = all(math.hypot(x - d.center_m[0], y - d.center_m[1]) > r + d.radius_m + 1.0 for d in discs)
        if apart and _clear_of_ends(x, y, r):
            discs.append(Disc((x, y), r))
    return tuple(discs)


def _blocks(rng: np.random.Generator, count: int) -> tuple[Polygon, ...]:
    """``count`` rectangles, 1-6 m a side, any orientation, clear of the ends (overlaps allowed)."""
    blocks: list[Polygon] = []
    for _ in range(100 * count):
        if len(blocks) == count:
            break
        x, y = float(rng.uniform(8.0, 72.0)), float(rng.uniform(2.0, 38.0))
        a, b, angle = float(rng.uniform(1.0, 6.0)), float(rng.uniform(1.0, 6.0)), float(rng.uniform(0.0, math.pi))
        if not _clear_of_ends(x, y, 0.5 * math.hypot(a, b)):
            continue
        c, s = math.cos(angle), math.sin(angle)
        half = ((-a / 2, -b / 2), (a / 2, -b / 2), (a / 2, b / 2), (-a / 2, b / 2))
        blocks.append(Polygon(tuple((x + c * u - s * v, y + s * u + c * v) for u, v in half)))
    return tuple(blocks)
