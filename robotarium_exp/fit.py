"""Does an experiment fit the Robotarium? One verdict, with each reason and its fix.

`fit_of_flight` judges the data a flight carries (what a submission embeds: the robots, the tube, the start
formation, the parking slots), so that the file's check judges exactly what the scene's commands judged;
`robotarium_fit` is the verdict on a scene. ``vtube scene show``, ``plan``, ``robotarium run``, ``robotarium
compare``, ``submission build`` and ``submission check`` all ask here.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.design import INITIALIZER_APART_M, start_formation
from robotarium_exp.errors import ExperimentError
from robotarium_exp.experiment import TUBE_EDGE_POINTS, ExperimentConfig, flight_data
from robotarium_exp.flight_data import FlightData
from robotarium_exp.packing import packing_bound
from robotarium_exp.packing_proof import refuted
from robotarium_exp.parking_slots import (
    PARKING_LANES_MAX,
    PARKING_NEAREST_M,
    PARKING_SPACING_M,
    PARKING_WALL_M,
    parking_bound,
)
from robotarium_exp.safety import WALL_KEEP_M
from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.geometry.scene import Scene
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import first_narrowing
from vtube_planning.onboard import SampledTube

FloatArray = NDArray[np.float64]

ROUNDING_M = 2e-5
"""What the flight data's six significant digits may take off a gap (5e-6 m per coordinate in the arena): a start
formation built exactly the spacing apart on a bend carries gaps of 0.399997 m."""


@dataclass(frozen=True)
class Misfit:
    """One reason an experiment does not fit the testbed, and what to change; ``kind`` names the rule for the fix
    of a generated tube (`for_map_file`), ``metres`` and ``robots`` the lengthening and the robots that fit."""

    what: str
    fix: str
    kind: str = ''
    metres: float = 0.0
    robots: int = 0

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


def robotarium_fit(scene: Scene, *, prove: bool = False) -> Fit:
    """The verdict on a scene flown on the Robotarium (its formation, tube and parking slots); a tube generated from
    a map file is told in the map file's keys (`for_map_file`). With ``prove``, a start formation refused where
    Oler's bound allows the robots is also tried by `robotarium_exp.packing_proof.refuted` (15 s to 6 minutes on
    the sweep's tubes)."""
    formation = start_formation(scene.tube, scene.swarm.n_robots)
    if formation.problem is None:
        data = flight_data(scene, None, ExperimentConfig(planning=False))
        fit = fit_of_flight(data)
        if any(misfit.kind == 'narrowing' for misfit in fit.misfits):
            fit = fit_of_flight(data, robots_before_narrowing(scene.tube, scene.swarm.n_robots))
        fit = _said_physical(fit, scene.tube, scene.swarm.n_robots, prove)
    else:
        left, right = scene.tube.boundaries(np.linspace(0.0, scene.tube.length_m, TUBE_EDGE_POINTS))
        fit = Fit(
            (
                *_robots(scene.swarm.n_robots),
                *_tube_inside(np.stack([left.T, right.T])),
                Misfit(
                    f'no start formation: {formation.problem}', 'move the tube entrance inwards or widen it', 'entrance'
                ),
            )
        )
    if GENERATED not in scene.text:
        return fit
    return Fit(tuple(for_map_file(misfit, scene) for misfit in fit.misfits))


def _said_physical(fit: Fit, tube: VirtualTube, n_robots: int, prove: bool) -> Fit:
    """``fit`` with its refusals said physical where no layout holds the robots: the start formation's (robots
    outside the box or past the narrowing) above `robotarium_exp.packing.packing_bound` or, with ``prove``, where
    `robotarium_exp.packing_proof.refuted` proves it; the parking slots' above
    `robotarium_exp.parking_slots.parking_bound`. Any other such refusal says it is not shown to be physical, and
    how many robots the bound lets stand (and, with ``prove``, that the proof does not rule them out)."""
    said = {  # the misfits' kinds: the bound, where, its module, and the proof within it (if any)
        ('box', 'narrowing'): (
            packing_bound,
            f'fit {ROBOTARIUM.ic_spacing_m} m apart in the start region',
            'packing',
            refuted,
        ),
        ('parking',): (parking_bound, f'park {PARKING_SPACING_M} m apart beyond the exit', 'parking_slots', None),
    }
    misfits = list(fit.misfits)
    for kinds, (bound_of, where, module, proof) in said.items():
        if not any(misfit.kind in kinds for misfit in misfits):
            continue
        bound, how = bound_of(tube), f"Oler's bound, robotarium_exp.{module}"
        asked = proof if prove and n_robots <= bound else None  # the proof, where it is asked for
        if asked is not None and asked(tube, n_robots):
            bound, how = n_robots - 1, 'proved by branch and bound, robotarium_exp.packing_proof'
        if n_robots > bound:
            note = f' (physically: at most {bound} robots {where}, in any layout; {how})'
        else:
            not_out = f'; robotarium_exp.packing_proof does not rule {n_robots} out' if asked else ''
            note = f" (not shown to be physical: Oler's bound lets up to {bound} robots {where}{not_out})"
        misfits = [replace(m, what=m.what + note) if m.kind in kinds else m for m in misfits]
    return Fit(tuple(misfits))


GENERATED = '# generated by `vtube tube generate`'
"""The line a scene file written by `vtube tube generate` carries (`vtube_planning.geometry.from_maps.map_file`)."""


def for_map_file(misfit: Misfit, scene: Scene) -> Misfit:
    """``misfit`` with its fix in the keys of the map file the user edits ([tube.generate]), for a generated tube;
    a lengthening the arena has no room for is not proposed."""
    fewer = f'use at most {misfit.robots} robots' if misfit.robots else 'use fewer robots'
    fixes = {
        'entrance': 'in the map file, move start_m inwards (the start formation lies behind it) or raise half_width_max_m',
        'box': f'in the map file, move start_m inwards (the start formation lies behind it), or {fewer}',
        'tube': 'in the map file, move start_m and goal_m inwards or lower half_width_max_m',
        'width': f'in the map file, raise half_width_min_m to at least {WALL_KEEP_M:g} m',
        'parking': f'in the map file, move goal_m away from the arena edge (the slots lie beyond it), or {fewer}',
    }
    if misfit.kind == 'narrowing':
        start, back = scene.tube.center_at(0.0), -np.asarray(scene.tube.tangent(0.0), dtype=float)
        moved = start + misfit.metres * back
        room = bool(np.all(np.abs(moved) <= np.array(ROBOTARIUM.ic_box_m)))
        fixes['narrowing'] = (
            f'in the map file, move start_m {misfit.metres:.2f} m further back from the narrow passage, to '
            f'({moved[0]:.2f}, {moved[1]:.2f}), or {fewer}'
            if room
            else f'the arena has no room to move start_m {misfit.metres:.2f} m back (to ({moved[0]:.2f}, '
            f'{moved[1]:.2f}), outside the box the testbed starts robots in): {fewer}'
        )
    return Misfit(misfit.what, fixes.get(misfit.kind, misfit.fix), misfit.kind, misfit.metres, misfit.robots)


def robots_before_narrowing(tube: VirtualTube, n_robots: int) -> int:
    """The most robots, fewer than ``n_robots``, whose start formation (`robotarium_exp.design.start_formation`:
    plain rows, the queue, staggered rows) ends before the tube's first narrowing; 0 when none does."""
    narrowing = first_narrowing(*tube.width.knots)
    for k in range(n_robots - 1, 0, -1):
        formation = start_formation(tube, k)
        if formation.problem is None and (narrowing is None or formation.l_front_m <= narrowing.start_m + 1e-6):
            return k
    return 0


def fit_of_flight(data: FlightData, fitting: int | None = None) -> Fit:
    """The verdict on the data a flight carries; ``fitting``: how many robots would start before the narrowing
    (`robots_before_narrowing`; None: counted from the data's own rows)."""
    misfits = [
        *_robots(data.n_robots),
        *_tube_inside(data.tube_edges_m),
        *_tube_wide_enough(data.tube.l_m, data.tube.half_width_m),
        *_formation_inside(data.initial_conditions),
        *_formation_spacing(data.initial_conditions),
        *_initializer_order(data.initial_conditions),
        *_formation_before_narrowing(data, fitting),
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
                    'tube',
                )
            ]
    return []


def _tube_wide_enough(l_m: FloatArray, half_width_m: FloatArray) -> list[Misfit]:
    """The tube keeps a robot's control point WALL_KEEP_M off its nearer wall everywhere (the safety filter's wall
    rows, `robotarium_exp.safety`): where it is narrower, the rows stop the swarm at the mouth (a tube 0.10 m wide:
    both robots held before it to the step limit)."""
    narrowest = int(np.argmin(half_width_m))
    if half_width_m[narrowest] >= WALL_KEEP_M:
        return []
    return [
        Misfit(
            f'the tube narrows to {2 * half_width_m[narrowest]:.2f} m at l = {l_m[narrowest]:.2f} m, under the '
            f"{2 * WALL_KEEP_M:.2f} m a robot passes through (its body and the safety filter's margin to each wall)",
            f'widen it to at least {2 * WALL_KEEP_M:.2f} m there',
            'width',
        )
    ]


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
            'box',
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


def _formation_before_narrowing(data: FlightData, fitting: int | None) -> list[Misfit]:
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
    if fitting is None:
        rows_fitting = int((start - back + 1e-6) // pitch) + 1 if start >= back else 0
        fitting = rows_fitting * columns if 0 < rows_fitting < rows else 0
    fewer = f', or use at most {fitting} robots' if fitting else ''
    return [
        Misfit(
            f'the start formation ({rows} row(s) of up to {columns}) reaches l = {front:.2f} m, past the start of the '
            f'narrowing at l = {start:.2f} m: the swarm would start inside it, {_no_queue(samples.xy_m[:, 0])}',
            f'lengthen the wide part before the narrowing by {front - start:.2f} m{fewer}',
            'narrowing',
            front - start,
            fitting,
        )
    ]


def _no_queue(entrance: FloatArray) -> str:
    """Why the rows cannot queue behind the entrance instead (`robotarium_exp.design.entry_queue`, theory §12)."""
    box = np.array(ROBOTARIUM.ic_box_m)
    if np.any(np.abs(entrance) > box):
        return (
            f'and no robot can queue behind the entrance at ({entrance[0]:.2f}, {entrance[1]:.2f}), outside the box '
            f'|x| <= {box[0]}, |y| <= {box[1]} the testbed initializes robots in'
        )
    return 'and queued behind the entrance the rows would leave the box the testbed initializes robots in'


def _parking_inside(data: FlightData) -> list[Misfit]:
    """The parking slots keep the design's wall (less the data's rounding) from the arena's edge, and lie beyond the
    exit (`robotarium_exp.parking_slots.parking`)."""
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
            f'slots stand {PARKING_SPACING_M} m apart in up to {PARKING_LANES_MAX} lanes or in staggered rows, all '
            'beyond the exit) or use fewer robots',
            'parking',
        )
    ]


def require_fit(scene: Scene) -> None:
    """Refuse a scene that does not fit the Robotarium, before anything flies
    ([`ExperimentError`][robotarium_exp.errors.ExperimentError])."""
    fit = robotarium_fit(scene)
    if not fit.fits:
        raise ExperimentError(f'scene {scene.name!r} {fit.reason}')
