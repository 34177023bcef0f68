"""Does an experiment fit the Robotarium? One verdict, with each reason and its fix.

`fit_of_flight` judges the data a flight carries (what a submission embeds: the robots, the tube, the start
formation, the parking slots), so that the file's check judges exactly what the scene's commands judged;
`robotarium_fit` is the verdict on a scene. ``vtube scene show``, ``plan``, ``robotarium run``, ``robotarium
compare``, ``submission build`` and ``submission check`` all ask here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.design import (
    INITIALIZER_APART_M,
    PARKING_LANES_MAX,
    PARKING_NEAREST_M,
    PARKING_SPACING_M,
    PARKING_WALL_M,
    start_formation,
)
from robotarium_exp.errors import ExperimentError
from robotarium_exp.experiment import TUBE_EDGE_POINTS, ExperimentConfig, flight_data
from robotarium_exp.flight_data import FlightData
from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.geometry.scene import Scene
from vtube_planning.geometry.width import first_narrowing
from vtube_planning.onboard import SampledTube

FloatArray = NDArray[np.float64]

ROUNDING_M = 2e-5
"""What the flight data's six significant digits may take off a gap (5e-6 m per coordinate in the arena): a start
formation built exactly the spacing apart on a bend carries gaps of 0.399997 m."""


@dataclass(frozen=True)
class Misfit:
    """One reason an experiment does not fit the testbed, and what to change."""

    what: str
    fix: str

    def __str__(self) -> str:
        return f'{self.what}; {self.fix}'


@dataclass(frozen=True)
class Fit:
    """The verdict: every reason the experiment does not fit (none: it fits)."""

    misfits: tuple[Misfit, ...] = ()

    @property
    def fits(self) -> bool:
        """Nothing keeps the experiment off the testbed."""
        return not self.misfits

    @property
    def reason(self) -> str:
        """One line: 'fits the Robotarium', or the first reason and its fix."""
        return 'fits the Robotarium' if self.fits else f'does not fit the Robotarium: {self.misfits[0]}'


def robotarium_fit(scene: Scene) -> Fit:
    """The verdict on a scene flown on the Robotarium (its formation, tube and parking slots)."""
    formation = start_formation(scene.tube, scene.swarm.n_robots)
    if formation.problem is None:
        return fit_of_flight(flight_data(scene, None, ExperimentConfig(planning=False)))
    left, right = scene.tube.boundaries(np.linspace(0.0, scene.tube.length_m, TUBE_EDGE_POINTS))
    misfits = [
        *_robots(scene.swarm.n_robots),
        *_tube_inside(np.stack([left.T, right.T])),
        Misfit(f'no start formation: {formation.problem}', 'move the tube entrance inwards or widen it'),
    ]
    return Fit(tuple(misfits))


def fit_of_flight(data: FlightData) -> Fit:
    """The verdict on the data a flight carries."""
    misfits = [
        *_robots(data.n_robots),
        *_tube_inside(data.tube_edges_m),
        *_formation_inside(data.initial_conditions),
        *_formation_spacing(data.initial_conditions),
        *_initializer_order(data.initial_conditions),
        *_formation_before_narrowing(data),
        *_parking_inside(data),
    ]
    return Fit(tuple(misfits))


def _robots(n: int) -> list[Misfit]:
    if 1 <= n <= ROBOTARIUM.max_robots:
        return []
    return [Misfit(f'{n} robots', f'the testbed has {ROBOTARIUM.max_robots}: use 1 to {ROBOTARIUM.max_robots}')]


def _tube_inside(edges_m: FloatArray) -> list[Misfit]:
    """The tube's boundaries (2, 2, K) inside the arena less its margin."""
    margin = ROBOTARIUM.arena_margin_m
    for side, edge in zip(('left', 'right'), edges_m, strict=True):
        outside = ROBOTARIUM.outside_arena(edge, margin)
        if outside.any():
            x, y = edge[:, int(np.argmax(outside))]
            return [
                Misfit(
                    f"the tube's {side} boundary reaches ({x:.2f}, {y:.2f}), outside the arena "
                    f'{ROBOTARIUM.arena_text} less {margin} m',
                    'move or shrink the tube',
                )
            ]
    return []


def _formation_inside(ic: FloatArray) -> list[Misfit]:
    box = np.array(ROBOTARIUM.ic_box_m)
    outside = np.any(np.abs(ic[:2].T) > box + 1e-9, axis=1)
    if not outside.any():
        return []
    k = int(np.argmax(outside))
    return [
        Misfit(
            f'robot {k} starts at ({ic[0, k]:.2f}, {ic[1, k]:.2f}), outside the box |x| <= {box[0]}, |y| <= {box[1]} '
            'the testbed initializes robots in',
            'move the tube entrance inwards, lengthen the wide part or use fewer robots',
        )
    ]


def _formation_spacing(ic: FloatArray) -> list[Misfit]:
    n = ic.shape[1]
    if n < 2:
        return []
    gaps = np.hypot(*(ic[:2, :, None] - ic[:2, None, :]))[np.triu_indices(n, 1)]
    spacing = ROBOTARIUM.ic_spacing_m
    if gaps.min() >= spacing - ROUNDING_M:
        return []
    return [
        Misfit(
            f'two robots start {gaps.min():.3f} m apart, closer than the {spacing} m the initialization needs',
            'space the start formation (robotarium_exp.design.start_formation does)',
        )
    ]


def _initializer_order(ic: FloatArray) -> list[Misfit]:
    """Robots 0 and 1 more than `INITIALIZER_APART_M` apart wherever two slots are
    (`robotarium_exp.design.order_for_v2_initializer`)."""
    gaps = np.hypot(*(ic[:2, :, None] - ic[:2, None, :]))
    if ic.shape[1] < 3 or gaps[0, 1] > INITIALIZER_APART_M or gaps.max() <= INITIALIZER_APART_M:
        return []
    return [
        Misfit(
            f"robots 0 and 1 start {gaps[0, 1]:.2f} m apart: V2's initializer never rescues robots 0 and 1 from "
            f'a deadlock, and within {INITIALIZER_APART_M} m of each other they can block each other for good '
            '(documentation: On the Robotarium, §2.6)',
            'reorder the robots with robotarium_exp.design.order_for_v2_initializer',
        )
    ]


def _formation_before_narrowing(data: FlightData) -> list[Misfit]:
    """The start formation's front row lies before the tube first narrows: a swarm that starts inside the narrowing
    is squeezed before it has started (a narrowing inside a bend, eight robots: 219 robot-steps with bodies up to
    0.2 m over the walls). *Measured*: the stricter rule this replaced, the formation's centre a look-ahead
    (`robotarium_exp.design.look_ahead`) before the narrowing, refused 27 of the sweep's cases with N <= 12
    (``docs/sweep/``); this one refuses 15 of them, and the other 12 pass the sweep's bar with V2's initialization
    (every robot through and parked, no body on a wall, the dip's density error at most 25 %)."""
    samples = data.tube
    narrowing = first_narrowing(samples.l_m, samples.half_width_m)
    if narrowing is None:
        return []
    start = narrowing.start_m
    l_m = (
        SampledTube(samples.l_m, samples.xy_m, samples.half_width_m, samples.area_m2)
        .project(data.initial_conditions[:2])
        .l_m
    )
    front, back = float(l_m.max()), float(l_m.min())
    if front <= start + 1e-6:
        return []
    # a row's robots lie on one cross-section, rows a spacing apart (the sampled tube projects a row on a bend
    # within millimetres, which rounding to a centimetre could split)
    ordered = np.sort(l_m)
    row_sizes = np.diff(np.flatnonzero(np.r_[True, np.diff(ordered) > 0.5 * ROBOTARIUM.ic_spacing_m, True]))
    rows, columns = row_sizes.size, int(row_sizes.max())
    pitch = max(ROBOTARIUM.ic_spacing_m, (front - back) / max(rows - 1, 1))  # a bend spreads the rows
    fitting = int((start - back + 1e-6) // pitch) + 1 if start >= back else 0
    fewer = f', or use at most {fitting * columns} robots' if 0 < fitting < rows else ''
    return [
        Misfit(
            f'the start formation ({rows} row(s) of up to {columns}) reaches l = {front:.2f} m, past the start of the '
            f'narrowing at l = {start:.2f} m: the swarm would start inside it',
            f'lengthen the wide part before the narrowing by {front - start:.2f} m{fewer}',
        )
    ]


def _parking_inside(data: FlightData) -> list[Misfit]:
    """The parking slots keep the design's wall (less the data's rounding) from the arena's edge, and lie beyond the
    exit (`robotarium_exp.design.parking`)."""
    slots, end = data.parking_slots, data.tube.xy_m[:, -1]
    tangent = data.tube.xy_m[:, -1] - data.tube.xy_m[:, -2]
    beyond = (tangent / np.hypot(*tangent)) @ (slots - end[:, None])
    outside = ROBOTARIUM.outside_arena(slots, PARKING_WALL_M - ROUNDING_M)
    behind = beyond < PARKING_NEAREST_M - ROUNDING_M
    if not (outside.any() or behind.any()):
        return []
    k = int(np.argmax(outside | behind))
    where = (
        f'outside the arena {ROBOTARIUM.arena_text} less {PARKING_WALL_M} m'
        if outside[k]
        else f'{beyond[k]:.2f} m beyond the exit, less than {PARKING_NEAREST_M} m'
    )
    return [
        Misfit(
            f'parking slot {k} lies at ({slots[0, k]:.2f}, {slots[1, k]:.2f}), {where}',
            f'move the tube exit at ({end[0]:.2f}, {end[1]:.2f}) away from the arena edge (its {data.n_robots} '
            f'slots lie in up to {PARKING_LANES_MAX} lanes and rows {PARKING_SPACING_M} m apart, all beyond the '
            'exit) or use fewer robots',
        )
    ]


def require_fit(scene: Scene) -> None:
    """Refuse a scene that does not fit the Robotarium, before anything flies
    ([`ExperimentError`][robotarium_exp.errors.ExperimentError])."""
    fit = robotarium_fit(scene)
    if not fit.fits:
        raise ExperimentError(f'scene {scene.name!r} {fit.reason}')
