"""The simulated swarm's initial formation: a grid before the entrance, moving along the tube, or positions given
by the caller (a Robotarium scene's entry formation, so that a simulation starts where the testbed's robots do)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from vtube_planning._validate import as_points
from vtube_planning.errors import ParamsError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.params import SwarmParams

FloatArray = NDArray[np.float64]
Positions = tuple[tuple[float, ...], tuple[float, ...]]
"""Points (2, N) as two rows, the x and the y of each robot: immutable, so a frozen configuration holds and compares
them."""


def as_positions(value: object, name: str = 'initial_positions_m') -> Positions:
    """``value`` (any (2, N) array-like, N >= 1, finite) as `Positions`, or `ShapeError` naming the
    problem."""
    points = as_points(value, name=name, item='robots', min_count=1)
    return tuple(points[0].tolist()), tuple(points[1].tolist())


def start_formation(
    tube: VirtualTube, swarm: SwarmParams, given: Positions | None, seed: int, jitter_m: float
) -> FloatArray:
    """The swarm's positions at t = 0, (2, N): ``given`` as it is (one column per robot of ``swarm``, not jittered),
    else `initial_formation` jittered by a generator seeded with ``seed``."""
    if given is None:
        return initial_formation(tube, swarm, np.random.default_rng(seed), jitter_m)
    positions = np.array(given, dtype=np.float64)
    if positions.shape[1] != swarm.n_robots:
        msg = (
            f'{positions.shape[1]} initial positions were given for a swarm of {swarm.n_robots} robots; give one '
            f'position per robot, or fly {positions.shape[1]} robots.'
        )
        raise ParamsError(msg)
    return positions


def initial_formation(tube: VirtualTube, swarm: SwarmParams, rng: np.random.Generator, jitter_m: float) -> FloatArray:
    """Grid of N robots before the entrance, (2, N): spacing 2 r_a, as many columns as fit the entrance with r_a to
    spare, front row r_a before l = 0, each position jittered by ``jitter_m`` (standard deviation, m)."""
    spacing = 2.0 * swarm.r_a_m
    lam0 = float(tube.half_width(0.0))
    fit = math.floor(2.0 * (lam0 - swarm.r_a_m) / spacing) + 1
    if fit < 1:
        msg = (
            f'the entrance (half-width {lam0:g} m) is too narrow for one robot with its avoidance radius '
            f'r_a = {swarm.r_a_m:g} m; widen the tube or lower r_a_m.'
        )
        raise ParamsError(msg)
    cols = max(1, min(swarm.n_side, fit))
    rows = math.ceil(swarm.n_robots / cols)
    points = []
    for row in range(rows):
        in_row = min(cols, swarm.n_robots - row * cols)
        l_row = -swarm.r_a_m - spacing * row
        for c in range(in_row):
            y = (c - 0.5 * (in_row - 1)) * spacing
            points.append(tube.center_at(l_row) + y * tube.normal(l_row))
    positions = np.array(points).T
    jittered: FloatArray = positions + jitter_m * rng.standard_normal(positions.shape)
    return jittered
