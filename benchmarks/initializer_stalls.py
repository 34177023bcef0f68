"""How often V2's initializer stalls on the sweep's start formations, under the current rule and variants of it.

    python -m benchmarks.initializer_stalls [--formations s_curve:4 ...] [--variants current heading_up ...]
        [--seeds 150] [--first 1000] [--limit 15000] [--workers 2] [--trace SEED]

Prints one row per formation x variant: runs stuck (not at the initial conditions within ``--limit`` steps) of
runs, the median and 90 % duration (simulated s) of those that finished, the turn the flight needs at its start
(the largest heading difference between a slot's pose and the tube's tangent there) and the formation's front
row against the first narrowing (a variant that pushes the formation into the narrowing does not fit the sweep).
The runs are `robotarium_exp.initializer.initializer_durations`'s (V2's initializer, step for step).

The variants (implemented here, not in ``robotarium_exp``; the current rule is
`robotarium_exp.design.start_formation`):

- ``current``: the start formation as built (rows 0.4 m apart, headings along the tube, robot 0 on a slot with
  the fewest neighbours, front first, robot 1 more than 0.55 m from it: `robotarium_exp.design.order_for_v2_initializer`);
- ``least_crowded``: the rule it replaced, robots 0 and 1 on the two slots with the fewest neighbours, front first;
- ``heading_up``: the same slots and order, every heading pointing away from the nearer charger row (+90 degrees
  below y = 0, -90 degrees above), the approach of a robot from the nearer chargers (the flight turns them);
- ``spacing_0.5`` / ``spacing_0.6``: rows and columns 0.5 / 0.6 m apart (where the entrance has room);
- ``far_pair``: robots 0 and 1 on the pair of slots farthest apart among those with the fewest neighbours (or one
  more), the front one first;
- ``back_pair``: robots 0 and 1 on the back row's two outer slots;
- ``clear_path``: robots 0 and 1 on the slots whose straight line from the chargers is least often blocked.

``docs/robotarium.md`` §2.6 ("Where the initializer still stalls") has the measured table and the traced mechanism;
its ``apart`` rows are today's ``current``.
"""

from __future__ import annotations

import argparse
import dataclasses
import itertools
import math
from collections.abc import Callable
from unittest import mock

import numpy as np
from numpy.typing import NDArray

import robotarium_exp.rps.robotarium as simulator
from robotarium_exp import design
from robotarium_exp.initializer import initializer_durations
from robotarium_exp.scene import load_scene
from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.geometry.tube import VirtualTube

FloatArray = NDArray[np.float64]

FORMATIONS = {
    's_curve:4': ('docs/sweep/tubes/s_curve.toml', 4),
    's_curve:6': ('docs/sweep/tubes/s_curve.toml', 6),
    'bend35:4': ('docs/sweep/tubes/bend35.toml', 4),
    'bend35:6': ('docs/sweep/tubes/bend35.toml', 6),
    'bend60:4': ('docs/sweep/tubes/bend60.toml', 4),
    'narrowing_in_bend:6': ('docs/sweep/tubes/narrowing_in_bend.toml', 6),
    'robotarium_curve:6': ('robotarium_curve', 6),
    'robotarium_curve:8': ('robotarium_curve', 8),
    'narrow:8': ('docs/sweep/tubes/narrow.toml', 8),
    'robotarium_trapezoid:6': ('robotarium_trapezoid', 6),
    'robotarium_trapezoid:10': ('robotarium_trapezoid', 10),
}
"""The sweep's flying formations with N >= 4 (``docs/sweep/sweep.md``), as ``name:N``."""


def current(tube: VirtualTube, n: int) -> FloatArray:
    """The start formation as `robotarium_exp.design.start_formation` builds it."""
    return design.start_formation(tube, n).poses


def heading_up(tube: VirtualTube, n: int) -> FloatArray:
    """The current slots and order, headings away from the nearer charger row."""
    poses = current(tube, n)
    headings = np.where(poses[1] <= 0.0, np.pi / 2, -np.pi / 2)
    turned: FloatArray = np.vstack([poses[:2], headings])
    return turned


def spaced(spacing_m: float) -> Callable[[VirtualTube, int], FloatArray]:
    """The current rule with rows and columns ``spacing_m`` apart."""

    def build(tube: VirtualTube, n: int) -> FloatArray:
        with mock.patch.object(design, 'ROBOTARIUM', dataclasses.replace(ROBOTARIUM, ic_spacing_m=spacing_m)):
            return current(tube, n)

    return build


def _reordered(poses: FloatArray, first: list[int]) -> FloatArray:
    """``poses`` with the slots ``first`` as robots 0 and 1 (front first), the rest in their order."""
    ahead = poses[0] * np.cos(poses[2]) + poses[1] * np.sin(poses[2])
    first = sorted(first, key=lambda k: -float(ahead[k]))
    order = first + [k for k in range(poses.shape[1]) if k not in first]
    reordered: FloatArray = poses[:, order]
    return reordered


def far_pair(tube: VirtualTube, n: int) -> FloatArray:
    """Robots 0 and 1 on the pair farthest apart among the slots with the fewest neighbours (or one more)."""
    poses = current(tube, n)
    counts = design.neighbour_counts(poses)
    calm = [k for k in range(n) if counts[k] <= counts.min() + 1]
    pair = max(itertools.combinations(calm, 2), key=lambda p: float(np.hypot(*(poses[:2, p[0]] - poses[:2, p[1]]))))
    return _reordered(poses, list(pair))


def least_crowded(tube: VirtualTube, n: int) -> FloatArray:
    """The former rule: robots 0 and 1 on the two slots with the fewest neighbours, front first."""
    poses = current(tube, n)
    counts = design.neighbour_counts(poses)
    ahead = poses[0] * np.cos(poses[2]) + poses[1] * np.sin(poses[2])
    return _reordered(poses, sorted(range(n), key=lambda k: (counts[k], -round(float(ahead[k]), 6), k))[:2])


def back_pair(tube: VirtualTube, n: int) -> FloatArray:
    """Robots 0 and 1 on the back row's two outer slots (the two rearmost slots farthest apart)."""
    poses = current(tube, n)
    ahead = poses[0] * np.cos(poses[2]) + poses[1] * np.sin(poses[2])
    back = [k for k in range(n) if ahead[k] <= ahead.min() + 0.5 * ROBOTARIUM.ic_spacing_m]
    if len(back) < 2:
        back = [int(k) for k in np.argsort(ahead)[:2]]
    pair = max(itertools.combinations(back, 2), key=lambda p: float(np.hypot(*(poses[:2, p[0]] - poses[:2, p[1]]))))
    return _reordered(poses, list(pair))


CLEARANCE_M = 0.25
"""A straight approach passing closer than this to another slot counts as blocked: V2's unicycle barrier keeps
0.15 m + 2 x 0.05 m between the projection points, so no robot passes between two neighbours 0.4 m apart."""


def chargers() -> FloatArray:
    """V2's 22 charger slots (2, 22): 11 along the bottom edge and 11 along the top, a body's diameter inside."""
    x0, x1, y0, y1 = ROBOTARIUM.arena_m
    inset = 0.5 * ROBOTARIUM.robot_diameter_m
    x = np.repeat(np.linspace(x0 + inset, x1 - inset, 11), 2)
    y = np.tile([y0 + inset, y1 - inset], 11)
    slots: FloatArray = np.array([x, y])
    return slots


def blocked_share(poses: FloatArray) -> FloatArray:
    """Per slot, the share of chargers whose straight line to it passes within `CLEARANCE_M` of another slot."""
    start = chargers()
    n = poses.shape[1]
    share = np.zeros(n)
    for k in range(n):
        path = poses[:2, k : k + 1] - start  # (2, chargers): charger -> slot k
        others = np.delete(poses[:2], k, axis=1)  # (2, n - 1)
        rel = others[:, None, :] - start[:, :, None]  # (2, chargers, n - 1)
        along = np.clip((path[:, :, None] * rel).sum(axis=0) / (path**2).sum(axis=0)[:, None], 0.0, 1.0)
        gap = np.hypot(*(rel - along[None] * path[:, :, None]))
        share[k] = float(np.mean(gap.min(axis=1) < CLEARANCE_M)) if n > 1 else 0.0
    return share


def clear_path(tube: VirtualTube, n: int) -> FloatArray:
    """Robots 0 and 1 on the two slots whose straight approach from the chargers is least often blocked by
    another slot (ties: fewer neighbours, then the front one), robot 0 the clearer."""
    poses = current(tube, n)
    share, counts = blocked_share(poses), design.neighbour_counts(poses)
    ahead = poses[0] * np.cos(poses[2]) + poses[1] * np.sin(poses[2])
    first = sorted(range(n), key=lambda k: (round(float(share[k]), 6), counts[k], -round(float(ahead[k]), 6)))[:2]
    order = first + [k for k in range(n) if k not in first]
    reordered: FloatArray = poses[:, order]
    return reordered


VARIANTS: dict[str, Callable[[VirtualTube, int], FloatArray]] = {
    'current': current,
    'least_crowded': least_crowded,
    'heading_up': heading_up,
    'spacing_0.5': spaced(0.5),
    'spacing_0.6': spaced(0.6),
    'far_pair': far_pair,
    'back_pair': back_pair,
    'clear_path': clear_path,
}


def flight_turn_deg(tube: VirtualTube, poses: FloatArray) -> float:
    """The largest turn (degrees) from a slot's heading to the tube's tangent there."""
    tangent = tube.tangent(tube.project(poses[:2]).l_m)
    turn = np.arctan2(tangent[:, 1], tangent[:, 0]) - poses[2]
    return float(np.degrees(np.abs(np.arctan2(np.sin(turn), np.cos(turn))).max()))


def front_margin_m(tube: VirtualTube, poses: FloatArray) -> float:
    """From the formation's front slot to the first narrowing along the tube (m; inf: none, negative: inside)."""
    narrowing = design.first_narrowing(tube)
    front = float(np.max(tube.project(poses[:2]).l_m))
    return narrowing.start_m - front if narrowing is not None else math.inf


def row(formation: str, variant: str, seeds: range, limit: int, workers: int) -> str:
    """One table row: the formation built by the variant, run once per seed."""
    path, n = FORMATIONS[formation]
    tube = load_scene(path, n_robots=n).tube
    poses = VARIANTS[variant](tube, n)
    if np.isnan(poses).any():
        return f'| {formation} | {variant} | no formation | | | | | |'
    sample = initializer_durations(poses, seeds, limit, workers=workers)
    q = np.quantile(sample.durations_s, [0.5, 0.9]) if sample.durations_s else [math.nan, math.nan]
    stuck = ' '.join(str(s) for s in sample.stuck_seeds)
    return (
        f'| {formation} | {variant} | {len(sample.stuck_seeds)} of {sample.runs} | {q[0]:.1f} | {q[1]:.1f} | '
        f'{flight_turn_deg(tube, poses):.0f} | {front_margin_m(tube, poses):.2f} | {stuck} |'
    )


def trace(formation: str, variant: str, seed: int, limit: int) -> None:
    """Print where each robot started, where it stands after the run (at most ``limit`` steps) and why not done."""
    path, n = FORMATIONS[formation]
    ic = VARIANTS[variant](load_scene(path, n_robots=n).tube, n)
    seen: list[FloatArray] = []
    step = simulator.Robotarium.step

    def recording(self: simulator.Robotarium) -> None:
        seen.append(self._poses.copy())
        step(self)

    with mock.patch.object(simulator.Robotarium, 'step', recording):
        stuck = initializer_durations(ic, [seed], limit, workers=1).stuck_seeds
    start, end = seen[0], seen[-1]
    gaps = np.hypot(*(end[:2, :, None] - end[:2, None, :])) + np.diag(np.full(n, np.inf))
    turn = np.arctan2(np.sin(end[2] - ic[2]), np.cos(end[2] - ic[2]))
    print(f'{formation} {variant} seed {seed}: {"stuck" if stuck else "done"} after {len(seen)} steps')
    for k in range(n):
        print(
            f'robot {k}: charger ({start[0, k]:+.2f}, {start[1, k]:+.2f}), slot ({ic[0, k]:+.2f}, {ic[1, k]:+.2f}), '
            f'at ({end[0, k]:+.2f}, {end[1, k]:+.2f}) {np.hypot(*(end[:2, k] - ic[:2, k])):.3f} m from it, '
            f'heading off {turn[k]:+.2f} rad, nearest robot {int(np.argmin(gaps[k]))} at {gaps[k].min():.2f} m'
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--formations', nargs='+', default=list(FORMATIONS), choices=list(FORMATIONS))
    parser.add_argument('--variants', nargs='+', default=['current'], choices=list(VARIANTS))
    parser.add_argument('--seeds', type=int, default=150)
    parser.add_argument('--first', type=int, default=1000)
    parser.add_argument('--limit', type=int, default=15000, help='steps before a run counts as stuck')
    parser.add_argument('--workers', type=int, default=2)
    parser.add_argument('--trace', type=int, metavar='SEED', help='trace one seed of the first formation and variant')
    args = parser.parse_args()
    if args.trace is not None:
        trace(args.formations[0], args.variants[0], args.trace, args.limit)
        return
    seeds = range(args.first, args.first + args.seeds)
    print(
        '| formation | variant | stuck | median [s] | 90 % [s] | flight turn [deg] | front to narrowing [m] '
        '| stuck seeds |'
    )
    print('|---|---|---|---|---|---|---|---|')
    for formation, variant in itertools.product(args.formations, args.variants):
        print(row(formation, variant, seeds, args.limit, args.workers), flush=True)


if __name__ == '__main__':
    main()
