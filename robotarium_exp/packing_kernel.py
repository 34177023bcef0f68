"""The branch and bound of `robotarium_exp.packing_proof`, compiled (numba): boxes in (l, n), pruned and shaved.

A node is one box per robot, ``B[i] = (l from, l to, n from, n to)``: robot i stands at P(l, n) = gamma(l) + n nu(l)
for some (l, n) in its box, the robots sorted by l. The geometry ``geo`` is a tuple of tables sampled along the
centre line (`robotarium_exp.packing_proof.proof_region`): ``grid`` (origin, step), the centre and unit normal at
each sample, and range-maximum tables (`robotarium_exp.packing_proof.range_table`) of the half room, of kappa and
of -kappa; ``limits`` = (the spacing less the tolerance, the box's half sizes, the tolerance). Every bound is an
upper bound on a distance, so every pruned box is one where no layout lies:

- a box's centre is read at its nearest sample (l_k, n_c); every point of the box lies within
  r = sqrt((s a)^2 + h_n^2) of P(l_k, n_c) (a: the farthest l of the box from l_k, h_n: half its n side), since
  |dP/dl| = |1 - kappa n| <= s over the box and l_k (signed kappa: the inner side of a bend is shorter) and
  |dP/dn| = 1, orthogonal;
- two boxes' farthest points are at most min(centre distance + r_1 + r_2, sqrt((s' L)^2 + W^2)) apart (L, W: their
  joint extents in l and n, s' over both);
- a node where two robots' boxes are nearer than the spacing at their farthest, or a box lies wholly outside the
  initializer's box, holds no layout; an end slice of a box whose farthest points from some other robot's box are
  nearer than the spacing holds no robot of a layout, and is cut off (shaving).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
Geo = tuple[FloatArray, ...]
"""The kernel's tables (module doc)."""

SHAVE_PARTS = 8
"""Slices a box's side is tried in, from each end, for shaving."""
ROUNDS = 4
"""Rounds of ordering and shaving a node gets before it is split."""
_CAP = 50_000
"""Nodes the depth-first stack holds at most (a search's budget sizes it below that)."""
LEAST_SIDE_M = 1e-7
"""A box side `search` splits no further: a node left open below it is undecided."""


@numba.njit(cache=True, inline='always')
def _most(table: FloatArray, grid: FloatArray, low: float, high: float) -> float:
    """The most of a sampled quantity over arc lengths [low, high] (the samples either side too)."""
    last = table.shape[1] - 1
    i = min(max(math.floor((low - grid[0]) / grid[1]) - 1, 0), last)
    j = min(max(math.ceil((high - grid[0]) / grid[1]) + 1, 0), last)
    level = int(math.log2(j - i + 1))  # exact at powers of two, and a whole number's log2 lies no nearer another
    return float(max(table[level, i], table[level, j - (1 << level) + 1]))


@numba.njit(cache=True)
def _stretch(geo: Geo, l_from: float, l_to: float, n_from: float, n_to: float) -> float:
    """The most |1 - kappa n| over arc lengths [l_from, l_to] and offsets [n_from, n_to] (bilinear: at a corner)."""
    grid, kappa, minus = geo[0], geo[4], geo[5]
    most, least = _most(kappa, grid, l_from, l_to), -_most(minus, grid, l_from, l_to)
    return max(abs(1.0 - most * n_from), abs(1.0 - most * n_to), abs(1.0 - least * n_from), abs(1.0 - least * n_to))


@numba.njit(cache=True)
def _centre(geo: Geo, box: FloatArray, out: FloatArray) -> None:
    """A box's centre read at its nearest sample, into ``out`` = (x, y, r, e): every point of the box within r of
    (x, y), its centre's own point within e."""
    grid, centre, normal = geo[0], geo[1], geo[2]
    k = min(max(math.floor(((box[0] + box[1]) / 2.0 - grid[0]) / grid[1] + 0.5), 0), centre.shape[0] - 1)
    l_k, n_c = grid[0] + k * grid[1], (box[2] + box[3]) / 2.0
    s = _stretch(geo, min(box[0], l_k), max(box[1], l_k), box[2], box[3])
    out[0], out[1] = centre[k, 0] + n_c * normal[k, 0], centre[k, 1] + n_c * normal[k, 1]
    out[2] = math.hypot(s * max(box[1] - l_k, l_k - box[0]), (box[3] - box[2]) / 2.0)
    out[3] = s * abs((box[0] + box[1]) / 2.0 - l_k)


@numba.njit(cache=True)
def _near(geo: Geo, a: FloatArray, at: FloatArray, b: FloatArray, bt: FloatArray) -> bool:
    """Every point of box ``a`` lies nearer than the spacing to every point of box ``b`` (their centres ``at``,
    ``bt`` from `_centre`): the centres' distance and radii, or the straight path's length in (l, n), bound
    their farthest points below it (module doc)."""
    limit = geo[6][0] * (1.0 - 1e-12) - 1e-12
    apart = math.hypot(at[0] - bt[0], at[1] - bt[1])
    if apart + at[2] + bt[2] < limit:
        return True
    if apart - at[3] - bt[3] >= limit:  # the two centres' own points already lie the spacing apart
        return False
    s = _stretch(geo, min(a[0], b[0]), max(a[1], b[1]), min(a[2], b[2]), max(a[3], b[3]))
    return bool(math.hypot(s * max(b[1] - a[0], a[1] - b[0]), max(b[3] - a[2], a[3] - b[2])) < limit)


@numba.njit(cache=True)
def _dead(geo: Geo, boxes: FloatArray, centres: FloatArray, j: int, piece: FloatArray) -> bool:
    """No robot j of a layout stands in ``piece`` of its box: another robot's box lies within the spacing of all
    of it."""
    own = np.empty(4)
    _centre(geo, piece, own)
    for i in range(boxes.shape[0]):
        if i != j and _near(geo, piece, own, boxes[i], centres[i]):
            return True
    return False


@numba.njit(cache=True)
def _shave(geo: Geo, boxes: FloatArray, centres: FloatArray, j: int) -> int:
    """Cut dead end slices (1 / `SHAVE_PARTS` of a side) off robot j's box: 0 unchanged, 1 cut, 2 all dead."""
    changed = 0
    for side in range(4):
        low = 0 if side < 2 else 2
        for _ in range(SHAVE_PARTS):
            width = boxes[j, low + 1] - boxes[j, low]
            if width <= 1e-9:
                break
            step = width / SHAVE_PARTS if width > 4e-5 * SHAVE_PARTS else width
            piece = boxes[j].copy()
            if side % 2 == 0:
                piece[low + 1] = boxes[j, low] + step
            else:
                piece[low] = boxes[j, low + 1] - step
            if not _dead(geo, boxes, centres, j, piece):
                break
            if step >= width:
                return 2
            if side % 2 == 0:
                boxes[j, low] += step
            else:
                boxes[j, low + 1] -= step
            changed = 1
    if changed:
        _centre(geo, boxes[j], centres[j])
    return changed


@numba.njit(cache=True)
def _narrowed(geo: Geo, boxes: FloatArray, centres: FloatArray) -> bool:
    """Order the boxes by l, keep them in the room, and shave them, in place (their centres into ``centres``):
    False where no layout is left."""
    grid, room, limits = geo[0], geo[3], geo[6]
    k = boxes.shape[0]
    for _ in range(ROUNDS):
        for i in range(1, k):
            boxes[i, 0] = max(boxes[i, 0], boxes[i - 1, 0])
            boxes[k - 1 - i, 1] = min(boxes[k - 1 - i, 1], boxes[k - i, 1])
        for i in range(k):
            most = _most(room, grid, boxes[i, 0], boxes[i, 1])
            boxes[i, 2], boxes[i, 3] = max(boxes[i, 2], -most), min(boxes[i, 3], most)
            if boxes[i, 0] > boxes[i, 1] or boxes[i, 2] > boxes[i, 3]:
                return False
            _centre(geo, boxes[i], centres[i])
            if max(abs(centres[i, 0]) - limits[1], abs(centres[i, 1]) - limits[2]) > centres[i, 2] + limits[3]:
                return False
        changed = 0
        for j in range(k):
            cut = _shave(geo, boxes, centres, j)
            if cut == 2:
                return False
            changed += cut
        if changed == 0:
            break
    return True


@numba.njit(cache=True)
def _judged(geo: Geo, boxes: FloatArray) -> int:
    """A node, narrowed in place (`_narrowed`): 0 no layout in it, 1 undecided, 2 its box centres may be a layout
    within the tolerance (read at the nearest samples, less their error e, a tenth of a millimetre): a search that
    meets one stops, undecided. Not asking more (the exact spacing) keeps a depth-first search out of the slivers
    where layouts touch the spacing, which no pruning closes."""
    k, limits = boxes.shape[0], geo[6]
    centres = np.empty((k, 4))
    if not _narrowed(geo, boxes, centres):
        return 0
    for i in range(k):
        for j in range(i + 1, k):
            if _near(geo, boxes[i], centres[i], boxes[j], centres[j]):
                return 0
    for i in range(k):  # the centres' own points lie within e of those read
        if max(abs(centres[i, 0]) - limits[1], abs(centres[i, 1]) - limits[2]) > limits[3] + centres[i, 3]:
            return 1
        for j in range(i + 1, k):
            apart = math.hypot(centres[i, 0] - centres[j, 0], centres[i, 1] - centres[j, 1])
            if apart < limits[0] - centres[i, 3] - centres[j, 3]:
                return 1
    return 2


@numba.njit(cache=True)
def _widest(geo: Geo, boxes: FloatArray, first: int, last: int) -> tuple[int, int, float]:
    """Of robots first..last, the box side to split: (robot, 0 for l or 2 for n, its length in metres)."""
    best, robot, side = -1.0, first, 0
    for i in range(first, last + 1):
        along = (boxes[i, 1] - boxes[i, 0]) * _stretch(geo, boxes[i, 0], boxes[i, 1], boxes[i, 2], boxes[i, 3])
        if along > best:
            best, robot, side = along, i, 0
        if boxes[i, 3] - boxes[i, 2] > best:
            best, robot, side = boxes[i, 3] - boxes[i, 2], i, 2
    return robot, side, best


@numba.njit(cache=True)
def _halved(stack: FloatArray, top: int, boxes: FloatArray, robot: int, side: int) -> int:
    """Push the node ``boxes`` onto ``stack`` at ``top`` twice, robot's box halved across ``side`` (0: l, 2: n):
    the new top."""
    middle = (boxes[robot, side] + boxes[robot, side + 1]) / 2.0
    stack[top] = boxes
    stack[top + 1] = boxes
    stack[top, robot, side + 1], stack[top + 1, robot, side] = middle, middle
    return top + 2


@numba.njit(cache=True)
def search(geo: Geo, start: FloatArray, first: int, last: int, nodes: int) -> tuple[int, int]:
    """Depth first from the boxes ``start`` (k, 4), splitting only robots first..last: (0 no layout, 1 undecided:
    out of ``nodes`` or a node left open with its boxes below `LEAST_SIDE_M`, 2 a layout within the tolerance
    (`_judged`); the nodes looked at)."""
    stack = np.empty((min(_CAP, max(nodes, 0) + 2), start.shape[0], 4))  # a node adds one at most: none needs more
    stack[0] = start
    top, seen, verdict_at_end = 1, 0, 0
    while top > 0:
        top -= 1
        boxes = stack[top].copy()
        seen += 1
        if seen > nodes or top + 2 >= stack.shape[0]:
            return 1, seen
        verdict = _judged(geo, boxes)
        if verdict == 2:
            return 2, seen
        if verdict == 0:
            continue
        robot, side, length = _widest(geo, boxes, first, last)
        if length < LEAST_SIDE_M:  # within the tolerance of a layout, or nothing to split: open
            verdict_at_end = 1
            continue
        top = _halved(stack, top, boxes, robot, side)
    return verdict_at_end, seen


@numba.njit(cache=True)
def frontier_search(
    geo: Geo,
    start: FloatArray,
    first: int,
    last: int,
    inner: int,
    nodes: int,
    finest: float,
) -> tuple[int, int]:
    """Split only the frontier robots first..last; a node is closed where, their boxes given, robots 0..last (the
    frontier and those before it) or first..k-1 (it and those after) have no layout (`search`, ``inner`` nodes
    each): each is a part of the whole problem, so neither has a layout of all. (0 no layout, 1 undecided: out of
    ``nodes`` in all, a frontier box below ``finest`` metres still open, or a layout of all within the tolerance;
    the nodes looked at, the halves' too.)"""
    stack = np.empty((min(_CAP, max(nodes, 0) + 2), start.shape[0], 4))  # a node adds one at most: none needs more
    stack[0] = start
    top, seen, k = 1, 0, start.shape[0]
    while top > 0:
        top -= 1
        boxes = stack[top].copy()
        seen += 1
        if seen > nodes or top + 2 >= stack.shape[0]:
            return 1, seen
        verdict = _judged(geo, boxes)
        if verdict == 2:  # a layout of all, within the tolerance
            return 1, seen
        if verdict == 0:
            continue
        verdict, looked = search(geo, boxes[: last + 1].copy(), 0, first - 1, min(inner, nodes - seen))
        seen += looked
        if verdict == 0:
            continue
        verdict, looked = search(geo, boxes[first:].copy(), last - first + 1, k - first - 1, min(inner, nodes - seen))
        seen += looked
        if verdict == 0:
            continue
        robot, side, length = _widest(geo, boxes, first, last)
        if length < finest:
            return 1, seen
        top = _halved(stack, top, boxes, robot, side)
    return 0, seen
