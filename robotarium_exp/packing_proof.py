"""A proof that N robots cannot start in a tube's start region, in any layout, where Oler's bound allows them.

`robotarium_exp.packing.packing_bound` (Oler's inequality on the region's convex hull) says where more robots than
the region can hold are refused; on a narrow bent band it allows one or two robots more than fit. `refuted` proves
that ``n`` robots the spacing d = 0.4 m apart do not fit the start region (``robotarium_exp.packing`` and
``docs/theory.md`` §12), exact up to a tolerance of 1e-6 m, by interval branch and bound
(`robotarium_exp.packing_kernel`): each robot's place is a box of arc lengths l and offsets n from the centre line,
the point gamma(l) + n nu(l); the robots are sorted by l (any layout can be); a node whose boxes hold no layout
(two robots nearer than d at their boxes' farthest points, a box outside the initializer's box or the room) is
closed, and end slices of a box where no robot of a layout can stand are cut off.

Twelve robots' boxes are too many to split: `refuted` splits only the frontier's, the `FRONTIER` robots in the middle
of the order, and closes a node where, their boxes given, the robots before the frontier and the frontier, or the
frontier and the robots after it, have no layout (a search of `INNER_NODES`): each is part of the whole problem, so
where one has none, the whole has none. The frontier stands between the two halves, so neither packs flush
against a cut, as windows cut at one arc length do (which prove too little on an S-curve). A window of the region
(between two arc lengths) is proved the same way.

A refusal this proves is physical under the start region's rules, as Oler's is (`robotarium_exp.fit`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.packing import QUEUE_BEHIND_M, room_at, start_region
from robotarium_exp.packing_kernel import Geo, frontier_search
from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.geometry.tube import VirtualTube

FloatArray = NDArray[np.float64]

PROOF_TOLERANCE_M = 1e-6
"""What a pruned pair may lack of the spacing, and a pruned box of the initializer's box: the proof is that no
layout keeps the spacing less this."""
TABLE_SAMPLES = 8801
"""Arc lengths sampled for the tables and the region's ends (0.5 mm apart on the sweep's tubes; a table's samples
either side of a range count too)."""
EDGE_SAMPLES = 201
"""Offsets sampled across the room for the region's ends."""
FRONTIER = 3
"""Robots in the middle of the order whose boxes `refuted` splits."""
INNER_NODES = 2_000
"""Nodes each half gets, given the frontier's boxes."""
PROOF_NODES = 6_000_000
"""Nodes `refuted` may look at in all (the halves' too) before it decides nothing: twice the 2.8 million of the
hardest proof known, the S-curve's at N = 12 (`benchmarks/sweep_packing_bound.py`)."""
FINEST_M = 1e-4
"""A frontier box's side below which `refuted` stops splitting and decides nothing."""


@dataclass(frozen=True)
class ProofRegion:
    """The start region as the proof reads it: the tube; ``first_m`` to ``last_m``, the arc lengths between which
    its points inside the box lie; ``geo``, the kernel's tables (`robotarium_exp.packing_kernel`) sampled from
    behind the entrance to the region's end."""

    tube: VirtualTube
    first_m: float
    last_m: float
    geo: Geo


def range_table(values: FloatArray) -> FloatArray:
    """Sparse table (levels, samples): row p holds the most of the 2**p samples from each (the tail padded)."""
    levels = [values]
    while 2 ** len(levels) <= values.size:
        half = 2 ** (len(levels) - 1)
        levels.append(np.concatenate([np.maximum(levels[-1][:-half], levels[-1][half:]), levels[-1][-half:]]))
    return np.array(levels)


def proof_region(tube: VirtualTube) -> ProofRegion | None:
    """``tube``'s start region for the proof (None where no point of it lies inside the box). Its points inside
    the box lie between ``first_m`` and ``last_m``: beyond them, every point of a cross-section lies within
    ``slack`` of a point sampled (`TABLE_SAMPLES` along, `EDGE_SAMPLES` across: half an across step, an along step
    stretched, and the room's most change over one), and every such point lies farther than ``slack`` outside the
    box."""
    l_m = np.linspace(-QUEUE_BEHIND_M, start_region(tube).l_m[-1], TABLE_SAMPLES)
    room = room_at(tube, l_m) + 1e-9
    signed = np.asarray(tube.curvature(l_m), dtype=float)
    kappa = np.abs(signed) * 1.001 + 1e-9
    step = float(l_m[1] - l_m[0])
    across = np.linspace(-1.0, 1.0, EDGE_SAMPLES)
    centre, normal = tube.center_at(l_m), tube.normal(l_m)
    points = centre[:, None, :] + (across[None, :, None] * room[:, None, None]) * normal[:, None, :]
    slack = room.max() / (EDGE_SAMPLES - 1) + step * (1.0 + kappa.max() * room.max()) + np.abs(np.diff(room)).max()
    near = np.any(np.max(np.abs(points) - np.array(ROBOTARIUM.ic_box_m), axis=2) <= slack, axis=1) & (room > 1e-9)
    if not near.any():
        return None
    k = np.flatnonzero(near)
    first, last = float(l_m[max(k[0] - 1, 0)]), float(l_m[min(k[-1] + 1, l_m.size - 1)])
    limits = np.array([ROBOTARIUM.ic_spacing_m - PROOF_TOLERANCE_M, *ROBOTARIUM.ic_box_m, PROOF_TOLERANCE_M])
    slop = np.abs(signed) * 0.001 + 1e-9  # kappa between samples, as |kappa| above
    geo = (
        np.array([l_m[0], step]),
        centre,
        normal,
        range_table(room),
        range_table(signed + slop),
        range_table(-signed + slop),
        limits,
    )
    return ProofRegion(tube, first, last, geo)


def _start(region: ProofRegion, k: int, first_m: float, last_m: float) -> FloatArray:
    """k boxes (k, 4), each the arc lengths [first_m, last_m] and the room's offsets."""
    room = float(region.geo[3][0].max())
    return np.tile(np.array([first_m, last_m, -room, room]), (k, 1))


_REFUTED: dict[tuple[str, int, tuple[float, float] | None], bool] = {}
"""`refuted`'s answers by the tube's fingerprint, N and the window."""


def refuted(tube: VirtualTube, n_robots: int, window: tuple[float, float] | None = None) -> bool:
    """Proved: ``n_robots`` robots do not fit ``tube``'s start region in any layout (module doc; cached), or its
    part between the arc lengths of ``window``."""
    key = (tube.fingerprint(), n_robots, window)
    if key not in _REFUTED:
        region = proof_region(tube)
        if region is None:
            _REFUTED[key] = n_robots > 0
        else:
            first_m, last_m = (region.first_m, region.last_m) if window is None else window
            start = _start(region, n_robots, max(first_m, region.first_m), min(last_m, region.last_m))
            first = max(0, n_robots // 2 - FRONTIER // 2)
            last = min(n_robots, first + FRONTIER) - 1
            verdict, _ = frontier_search(region.geo, start, first, last, INNER_NODES, PROOF_NODES, FINEST_M)
            _REFUTED[key] = verdict == 0
    return _REFUTED[key]
