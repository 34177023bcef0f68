"""Seeded random obstacle maps with a passage to find: the families a study draws its environments from.

Every family makes an 80 m x 40 m map (the paper's scale: 60 m tubes, Table 1's swarm) with the start at the
middle of its left edge and the goal at the middle of its right edge, 2 m in, and the tube limits of the paper's
scenes (half-width 1.2 to 4.5 m, 0.3 m kept from the obstacles, turns no tighter than v_min^2 / a_n = 4 m):

- ``forest``: ``clutter`` discs (radius 0.8-2.5 m, at least 1 m apart), none within 6 m of the start or goal;
- ``blocks``: ``clutter`` rectangles (1-6 m by 1-6 m, any orientation), the same exclusions;
- ``bottleneck``: a wall across the map at a random x in [30, 50] m with one opening of full width ``width_m`` at
  a random height, and ``clutter`` discs on either side.

`random_map` draws one map of a family from its seed (numpy's ``default_rng``): the same family, seed and
difficulty give the same map on every machine. `scene_on_map` flies a scene's swarm through the tube
generated on such a map (the campaign axes ``map``, ``map_seed``, ``map_clutter`` and ``map_width_m``).
"""

from __future__ import annotations

import functools
import math
from dataclasses import replace

import numpy as np

from vtube_planning.errors import ParamsError
from vtube_planning.geometry.from_maps.generate import GeneratedTube, TubeSpec, generate_tube
from vtube_planning.geometry.obstacles import Disc, Obstacles, Polygon
from vtube_planning.geometry.scene import Scene
from vtube_planning.geometry.workspace import Workspace

FAMILIES = ('forest', 'blocks', 'bottleneck')
SIZE_M = (80.0, 40.0)
START_M, GOAL_M = (2.0, 20.0), (78.0, 20.0)
CLEAR_OF_ENDS_M = 6.0
"""No obstacle within this distance of the start or the goal."""
LIMITS = {'half_width_min_m': 1.2, 'half_width_max_m': 4.5, 'margin_m': 0.3, 'turn_radius_min_m': 4.0}
"""The tube's limits: the paper's narrowest and widest half-width (scenes A-D), Table 1's v_min^2 / a_n."""
CLUTTER, WIDTH_M = 30, 4.0
"""The default difficulty: obstacles per map, and the bottleneck's opening."""
WIDTH_RANGE_M = (1.0, 20.0)
"""The openings a bottleneck can have: from below 2 lambda_min (refused) to half the map's height."""


def random_map(family: str, seed: int, *, clutter: int = CLUTTER, width_m: float = WIDTH_M) -> TubeSpec:
    """The map of ``family`` (module doc) drawn from ``seed``, with ``clutter`` obstacles and, for ``bottleneck``,
    an opening ``width_m`` wide; a ValueError names an unknown family or a difficulty out of range."""
    if clutter < 0 or seed < 0 or not WIDTH_RANGE_M[0] <= width_m <= WIDTH_RANGE_M[1]:
        msg = (
            f'a random map needs seed >= 0, clutter >= 0 and an opening width_m in [{WIDTH_RANGE_M[0]:g}, '
            f'{WIDTH_RANGE_M[1]:g}] m; got seed {seed}, clutter {clutter}, width_m {width_m}.'
        )
        raise ValueError(msg)
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


def scene_on_map(scene: Scene, family: str, seed: int, *, clutter: int = CLUTTER, width_m: float = WIDTH_M) -> Scene:
    """``scene`` (its swarm, planning options and gains) with its tube replaced by the one generated on the map of
    `random_map`, the map's obstacles kept; [`TubeGenerationError`][vtube_planning.errors.TubeGenerationError] when the
    map is refused. The maps are at the paper's scale, so the scene must be one of the paper's size (not a
    testbed's)."""
    if scene.testbed is not None:
        msg = (
            f'scene {scene.name!r} is declared for the {scene.testbed}; the random maps are 80 m x 40 m, at the '
            "paper's scale: fly them with a scene of that scale (A-D or your own without a testbed table)."
        )
        raise ParamsError(msg)
    made = _generated(family, seed, clutter, width_m)
    where = f'{family} map {seed} (clutter {clutter}, opening {width_m:g} m)'
    return replace(
        scene,
        name=f'{scene.name} on the {where}',
        tube=made.tube,
        obstacles=random_map(family, seed, clutter=clutter, width_m=width_m).obstacles,
        workspace=None,
        source=f'{scene.source} on the {where}',
    )


@functools.lru_cache(maxsize=64)
def _generated(family: str, seed: int, clutter: int, width_m: float) -> GeneratedTube:
    """The tube of a random map, generated once per process (a campaign flies each map in several modes)."""
    return generate_tube(random_map(family, seed, clutter=clutter, width_m=width_m), name=f'{family}-{seed}')


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
