"""A proof that N robots cannot start in a tube's start region, in any layout, where Oler's bound allows them.

`robotarium_exp.packing.packing_bound` (Oler's inequality on the region's convex hull) says where more robots than
the region can hold are refused; on a narrow bent band it allows one or two robots more than fit. `refuted` proves
that ``n`` robots the spacing d = 0.4 m apart do not fit the start region (``robotarium_exp.packing`` and
``docs/theory.md`` §12) by two arguments, both exact up to a tolerance of 1e-6 m:

- **Windows.** `_holds` decides, by interval branch and bound, whether k robots fit the part of the region between
  two arc lengths: each robot's place is a box of arc lengths l and offsets n from the centre line, the point
  gamma(l) + n nu(l); a box lies within r = sqrt((s h_l)^2 + h_n^2) of its centre's point (half sizes h_l, h_n;
  the stretch |d point / dl| = |1 - kappa n| <= s = 1 + max|kappa| max|n| over the box), so two boxes whose centres'
  points are closer than d - r_1 - r_2 hold no pair, and a box whose centre's point lies farther than r outside
  the initializer's box holds no robot. Robots are sorted by l (any layout can be), the boxes are split where
  they are largest, and a window holds k robots (a witness: every box centre in the region and the spacing apart)
  or does not (every box pruned); a search that runs out of `PROOF_NODES` decides nothing.
- **Sorted by arc length.** In any layout sorted by l, robot i stands beyond every window [l_0, t] that holds no i
  robots, and before every window [t, l_1] that holds no n - i + 1 robots (l_0, l_1: where the region's points
  lie); where one window of each kind overlap, robot i has no place, and the layout does not exist. The windows'
  ends lie `PROOF_STEP_M` apart; every robot's walk gets the first of `PROOF_NODES`, the `REFINED` robots nearest
  a contradiction the next ones.

A refusal this proves is physical under the start region's rules, as Oler's is (`robotarium_exp.fit`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.packing import QUEUE_BEHIND_M, packed_in_window, room_at, start_region
from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.geometry.tube import VirtualTube

FloatArray = NDArray[np.float64]

PROOF_STEP_M = 0.0025
"""How far apart the windows' ends lie along the centre line."""
REFINED = 2
"""Robots nearest a contradiction whose windows get the next budgets."""
PROOF_STRIDE = 4
"""Ends a walk steps over at the first budget (1 cm); at the next budgets, one."""
PROOF_NODES = (200_000, 800_000, 3_200_000)
"""Boxes a window's branch and bound may look at before it decides nothing, budget by budget."""
PROOF_TOLERANCE_M = 1e-6
"""What a pruned pair may lack of the spacing, and a pruned box of the initializer's box: the proof is that no
layout keeps the spacing less this."""
TABLE_SAMPLES = 8801
"""Arc lengths sampled for the room and curvature tables and the region's ends (0.5 mm apart on the sweep's tubes;
a table's samples either side of a range count too)."""
EDGE_SAMPLES = 201
"""Offsets sampled across the room for the region's ends."""
_BATCH = 20_000
"""Boxes pruned and split at once."""


@dataclass(frozen=True)
class ProofRegion:
    """The start region as the proof reads it: the tube; ``first_m`` to ``last_m``, the arc lengths between which
    its points inside the box lie; range-maximum tables (`_range_table`) of the half room and of |kappa| sampled
    every ``step_m`` from ``origin_m`` (behind the entrance) to the region's end."""

    tube: VirtualTube
    origin_m: float
    first_m: float
    last_m: float
    step_m: float
    room: FloatArray
    curvature: FloatArray

    def most(self, table: FloatArray, low: FloatArray, high: FloatArray) -> FloatArray:
        """The most of a sampled quantity over arc lengths [``low``, ``high``] (the samples either side too), from
        its `_range_table`."""
        last = table.shape[1] - 1
        i = np.clip(np.floor((low - self.origin_m) / self.step_m).astype(int) - 1, 0, last)
        j = np.clip(np.ceil((high - self.origin_m) / self.step_m).astype(int) + 1, 0, last)
        level = np.log2(j - i + 1).astype(int)
        most: FloatArray = np.maximum(table[level, i], table[level, j - (1 << level) + 1])
        return most


def _range_table(values: FloatArray) -> FloatArray:
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
    kappa = np.abs(np.asarray(tube.curvature(l_m), dtype=float)) * 1.001 + 1e-9
    step = float(l_m[1] - l_m[0])
    across = np.linspace(-1.0, 1.0, EDGE_SAMPLES)
    points = (
        tube.center_at(l_m)[:, None, :] + (across[None, :, None] * room[:, None, None]) * tube.normal(l_m)[:, None, :]
    )
    slack = room.max() / (EDGE_SAMPLES - 1) + step * (1.0 + kappa.max() * room.max()) + np.abs(np.diff(room)).max()
    near = np.any(np.max(np.abs(points) - np.array(ROBOTARIUM.ic_box_m), axis=2) <= slack, axis=1) & (room > 1e-9)
    if not near.any():
        return None
    k = np.flatnonzero(near)
    first, last = float(l_m[max(k[0] - 1, 0)]), float(l_m[min(k[-1] + 1, l_m.size - 1)])
    return ProofRegion(tube, float(l_m[0]), first, last, step, _range_table(room), _range_table(kappa))


def _holds(region: ProofRegion, k: int, first_m: float, last_m: float, nodes: int) -> bool | None:
    """Whether ``k`` robots fit the region between arc lengths ``first_m`` and ``last_m`` (module doc): True (a
    witness), False (proved: no layout), None (undecided after ``nodes`` boxes)."""
    spacing, box = ROBOTARIUM.ic_spacing_m - PROOF_TOLERANCE_M, np.array(ROBOTARIUM.ic_box_m)
    pairs = np.triu_indices(k, 1)
    start = np.empty((1, k, 4))
    room = float(region.most(region.room, np.array([first_m]), np.array([last_m]))[0])
    start[0] = (first_m, last_m, -room, room)  # each box: l from, l to, n from, n to
    stack, seen = [start], 0
    while stack:
        boxes = stack.pop()
        seen += boxes.shape[0]
        if seen > nodes:
            return None
        for i in range(1, k):  # sorted by l: robot i stands no nearer the entrance than robot i - 1
            boxes[:, i, 0] = np.maximum(boxes[:, i, 0], boxes[:, i - 1, 0])
            boxes[:, k - 1 - i, 1] = np.minimum(boxes[:, k - 1 - i, 1], boxes[:, k - i, 1])
        low, high = boxes[..., 0], boxes[..., 1]
        room_most = region.most(region.room, low.ravel(), high.ravel()).reshape(low.shape)
        boxes[..., 2] = np.maximum(boxes[..., 2], -room_most)
        boxes[..., 3] = np.minimum(boxes[..., 3], room_most)
        boxes = boxes[np.all((boxes[..., 0] <= boxes[..., 1]) & (boxes[..., 2] <= boxes[..., 3]), axis=1)]
        if not boxes.size:
            continue
        kappa = region.most(region.curvature, boxes[..., 0].ravel(), boxes[..., 1].ravel()).reshape(boxes.shape[:2])
        l_mid, n_mid = boxes[..., 0:2].mean(axis=2), boxes[..., 2:4].mean(axis=2)
        n_most = np.abs(boxes[..., 2:4]).max(axis=2)
        stretch = 1.0 + kappa * n_most
        radius = np.hypot(stretch * (boxes[..., 1] - boxes[..., 0]), boxes[..., 3] - boxes[..., 2]) / 2.0
        centre = region.tube.center_at(l_mid.ravel()) + n_mid.ravel()[:, None] * region.tube.normal(l_mid.ravel())
        centre = centre.reshape(boxes.shape[:2] + (2,))
        gap = np.hypot(*(centre[:, pairs[0]] - centre[:, pairs[1]]).transpose(2, 0, 1))
        outside = np.max(np.abs(centre) - box, axis=2)
        keep = np.all(
            np.minimum(gap + radius[:, pairs[0]] + radius[:, pairs[1]], _farthest(region, boxes, n_most, pairs))
            >= spacing,
            axis=1,
        )
        keep &= np.all(outside <= radius + PROOF_TOLERANCE_M, axis=1)
        witness = keep & np.all(gap >= ROBOTARIUM.ic_spacing_m, axis=1) & np.all(outside <= 0.0, axis=1)
        if witness.any():  # the centres keep the spacing and the box; in the room too?
            l_at, n_at = l_mid[witness], n_mid[witness]
            if np.any(np.all(np.abs(n_at) <= room_at(region.tube, l_at.ravel()).reshape(l_at.shape), axis=1)):
                return True
        boxes, radius = boxes[keep], radius[keep]
        if boxes.size:
            stack.extend(np.array_split(_split(boxes, radius), max(1, 2 * boxes.shape[0] // _BATCH)))
    return False


def _farthest(
    region: ProofRegion, boxes: FloatArray, n_most: FloatArray, pairs: tuple[NDArray[np.intp], NDArray[np.intp]]
) -> FloatArray:
    """A bound on the farthest two points of each pair of boxes can be (m, pairs), given each box's most |n|
    ``n_most`` (m, k): along the straight path between them in (l, n), |d point| <= sqrt((s dl)^2 + dn^2),
    s = 1 + max|kappa| max|n| over both boxes and between."""
    one, two = boxes[:, pairs[0]], boxes[:, pairs[1]]
    low, high = np.minimum(one[..., 0], two[..., 0]), np.maximum(one[..., 1], two[..., 1])
    kappa = region.most(region.curvature, low.ravel(), high.ravel()).reshape(low.shape)
    along = (high - low) * (1.0 + kappa * np.maximum(n_most[:, pairs[0]], n_most[:, pairs[1]]))
    across = np.maximum(one[..., 3], two[..., 3]) - np.minimum(one[..., 2], two[..., 2])
    farthest: FloatArray = np.hypot(along, across)
    return farthest


def _split(boxes: FloatArray, radius: FloatArray) -> FloatArray:
    """Each row of ``boxes`` (m, k, 4) twice: its widest box (by radius) halved along its longer side."""
    rows, widest = np.arange(boxes.shape[0]), np.argmax(radius, axis=1)
    chosen = boxes[rows, widest]
    along_l = (chosen[:, 1] - chosen[:, 0]) >= (chosen[:, 3] - chosen[:, 2])
    side = np.where(along_l, 0, 2)
    middle = (chosen[rows, side] + chosen[rows, side + 1]) / 2.0
    lower, upper = boxes.copy(), boxes.copy()
    lower[rows, widest, side + 1] = middle
    upper[rows, widest, side] = middle
    return np.concatenate([lower, upper])


WITNESS_RESTARTS = 3
"""Seeded starts of `robotarium_exp.packing`'s search a window gets before its branch and bound: most windows that
hold the robots are told so at once."""
_REFUTED: dict[tuple[str, int], bool] = {}
"""`refuted`'s answers by the tube's fingerprint and N."""


def refuted(tube: VirtualTube, n_robots: int) -> bool:
    """Proved: ``n_robots`` robots do not fit ``tube``'s start region in any layout (module doc; cached)."""
    key = (tube.fingerprint(), n_robots)
    if key not in _REFUTED:
        region = proof_region(tube)
        _REFUTED[key] = n_robots > 0 if region is None else _Sorted(region, n_robots).refuted()
    return _REFUTED[key]


class _Sorted:
    """The sorted arc-length argument (module doc) for ``n`` robots: ``beyond[i]``, the window end robot i is
    proved to stand beyond (-1: none), ``before[i]`` the one it stands before (the number of ends: none)."""

    def __init__(self, region: ProofRegion, n: int) -> None:
        self.region, self.n = region, n
        self.ends = np.append(np.arange(region.first_m, region.last_m, PROOF_STEP_M), region.last_m)
        self.beyond = np.full(n + 2, -1)
        self.before = np.full(n + 2, self.ends.size)

    def refuted(self) -> bool:
        """Every robot's windows at the first budget, stepping `PROOF_STRIDE` ends (robots from the entrance
        beyond, from the end before), then the windows of the `REFINED` robots nearest a contradiction at the next
        budgets, end by end."""
        robots, stride = list(range(1, self.n + 1)), PROOF_STRIDE
        for nodes in PROOF_NODES:
            for i in robots:
                self._walk(self.beyond, i, nodes, stride)
            for i in reversed(robots):
                self._walk(self.before, i, nodes, -stride)
            for i in range(1, self.n + 1):  # what the robots before and after stand beyond and before
                self.beyond[i] = max(self.beyond[i], self.beyond[i - 1])
            for i in range(self.n, 0, -1):
                self.before[i] = min(self.before[i], self.before[i + 1])
            proved = self.beyond[1 : self.n + 1] >= 0
            if np.any(proved & (self.before[1 : self.n + 1] <= self.beyond[1 : self.n + 1])):
                return True
            gap = self.before[1 : self.n + 1] - np.maximum(self.beyond[1 : self.n + 1], 0)
            robots, stride = sorted(1 + np.argsort(gap, kind='stable')[:REFINED].astype(int)), 1
        return False

    def _walk(self, ends: NDArray[np.intp], i: int, nodes: int, step: int) -> None:
        """Robot i's window end in ``ends`` (``beyond``, step > 0; ``before``, step < 0) taken from its
        neighbour's (robot i - 1's beyond, robot i + 1's before) where that is further, then moved on by ``step``
        ends while each step is proved and no contradiction is reached."""
        neighbour = ends[i - 1] if step > 0 else ends[i + 1]
        ends[i] = max(ends[i], neighbour) if step > 0 else min(ends[i], neighbour)
        while self.beyond[i] < self.before[i]:
            to = min(max(ends[i] + step, 0), self.ends.size - 1)
            if to == ends[i]:
                return
            end = float(self.ends[to])
            window = (self.region.first_m, end) if step > 0 else (end, self.region.last_m)
            if not self._none_fit(i if step > 0 else self.n - i + 1, *window, nodes):
                return
            ends[i] = to

    def _none_fit(self, k: int, first_m: float, last_m: float, nodes: int) -> bool:
        """Proved: ``k`` robots do not fit between the two arc lengths."""
        if packed_in_window(self.region.tube, k, float(first_m), float(last_m), WITNESS_RESTARTS):
            return False
        return _holds(self.region, k, float(first_m), float(last_m), nodes) is False
