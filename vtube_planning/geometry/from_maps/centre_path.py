"""From an obstacle map to a centre curve: the clearance grid, the cheapest path through it, and the lines and arcs
that follow the path (steps 1-3 of `vtube_planning.geometry.from_maps.generate`)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage, sparse
from scipy.sparse import csgraph

from vtube_planning.errors import TubeGenerationError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece

if TYPE_CHECKING:
    from vtube_planning.geometry.from_maps.tube_spec import TubeSpec

FloatArray = NDArray[np.float64]

Box = tuple[float, float, float, float]
"""A rectangle: x_min, x_max, y_min, y_max (m)."""
End = tuple[float, float] | Box
"""An end of the tube: a point, or a rectangle to choose it in."""
_BATCH = 16
"""Segments that `_pulled_straight` tries at once."""


class CornerError(TubeGenerationError):
    """A corner of the path that no arc rounds (`_rounded`): the refusal, and the corner's place (x, y)."""

    def __init__(self, message: str, corner_m: tuple[float, float]) -> None:
        super().__init__(message)
        self.corner_m = corner_m


MAX_GRID_NODES = 2e7
"""The most nodes a search grid may hold (some 1.5 GB of arrays); a map that needs more is refused up front."""


class SearchGrid:
    """The search grid: node centres, their clearance, and the free nodes (room for the narrowest tube)."""

    def __init__(self, spec: TubeSpec) -> None:
        b, h = spec.bounds, spec.resolution_m
        self.spec = spec
        nodes_x, nodes_y = (b.x_max_m - b.x_min_m) / h, (b.y_max_m - b.y_min_m) / h
        if nodes_x * nodes_y > MAX_GRID_NODES:
            least = math.sqrt((b.x_max_m - b.x_min_m) * (b.y_max_m - b.y_min_m) / MAX_GRID_NODES)
            msg = (
                f'the search grid of the map ({b}) at resolution_m = {h:g} m would hold {nodes_x * nodes_y:.3g} '
                f'nodes, more than {MAX_GRID_NODES:.0e}; give [tube.generate] resolution_m = {least:.3g} or more, or '
                'a smaller [workspace].'
            )
            raise TubeGenerationError(msg)
        self.x = np.arange(b.x_min_m + 0.5 * h, b.x_max_m, h)
        self.y = np.arange(b.y_min_m + 0.5 * h, b.y_max_m, h)
        if self.x.size < 2 or self.y.size < 2:
            msg = f'the map ({b}) is smaller than two grid cells of resolution_m = {h}.'
            raise TubeGenerationError(msg)
        xx, yy = np.meshgrid(self.x, self.y, indexing='ij')
        nodes = np.column_stack([xx.ravel(), yy.ravel()])
        occupied = spec.obstacles.inside(nodes)
        for image in spec.obstacles.images:  # a node whose cell meets an occupied pixel: a pixel smaller than a
            occupied |= image.meets_squares(nodes, 0.5 * h)  # cell between nodes is not missed
        occupied = occupied.reshape(xx.shape)
        # the distance to the nearest occupied node, less half a cell's diagonal (an obstacle's edge lies within it
        # of an occupied node next to a free one; every point of an image's pixel lies in an occupied node's cell):
        # a lower bound of the clearance, for the search only
        to_obstacle = (
            ndimage.distance_transform_edt(~occupied) * h - 0.5 * math.sqrt(2.0) * h if occupied.any() else np.inf
        )
        # the map's edge counts as an obstacle for the search, except within the room of the start and goal, where
        # the tube may meet it head-on (the width's own bound takes the edge across the tube: TubeSpec.edge_reach)
        edge = b.clearance(nodes) - b.margin_m + spec.margin_m
        near_end = np.zeros(xx.shape, dtype=bool)
        for x_end, y_end in (spec.start_m, spec.goal_m):
            near_end |= np.hypot(self.x[:, None] - x_end, self.y[None, :] - y_end) <= 2 * spec.room_m
        edge = np.where(near_end, np.inf, edge.reshape(xx.shape))  # every node lies inside the map
        self.clear = np.minimum(np.maximum(to_obstacle, 0.0), edge)
        self.free = self.clear >= spec.room_m + 0.5 * math.sqrt(2.0) * h  # a step between nodes keeps the room

    def block(self, point: tuple[float, float], radius_m: float) -> None:
        """Take the nodes within ``radius_m`` of ``point`` out of the search (a corner no arc rounds: the next
        search routes another way, around the obstacle on its other side or between others)."""
        near = np.hypot(self.x[:, None] - point[0], self.y[None, :] - point[1]) <= radius_m
        self.free &= ~near

    def node(self, point: tuple[float, float], what: str) -> tuple[int, int]:
        room = float(self.spec.obstacles.clearance(np.array([point]))[0])
        inside = float(self.spec.bounds.clearance(np.array([point]))[0]) >= self.spec.bounds.margin_m
        if not inside:
            msg = f'the {what} ({point[0]:.3f}, {point[1]:.3f}) lies outside the map less its margin; move it.'
            raise TubeGenerationError(msg)
        if room < self.spec.room_m:
            msg = (
                f'the {what} ({point[0]:.3f}, {point[1]:.3f}) has {room:.3f} m of room to the nearest obstacle, '
                f'less than the narrowest tube needs ({self.spec.room_m:.3f} m: half_width_min_m, margin_m '
                'and 1 to 2 cm for the certificate); move it.'
            )
            raise TubeGenerationError(msg)
        i, j = np.abs(self.x - point[0]).argmin(), np.abs(self.y - point[1]).argmin()
        return int(i), int(j)

    def path(self) -> FloatArray:
        """The cheapest free path (k, 2) from start to goal, its ends the given points."""
        spec = self.spec
        ends = spec.search_ends
        start = self.node(ends[0], 'start' if spec.start_heading_deg is None else "end of the start's straight lead")
        goal = self.node(ends[1], 'goal' if spec.goal_heading_deg is None else "start of the goal's straight lead")
        index = np.arange(self.free.size).reshape(self.free.shape)
        source, target = int(index[start]), int(index[goal])
        distances, previous = csgraph.dijkstra(
            self._graph((start, goal)), directed=False, indices=source, return_predecessors=True
        )
        if not np.isfinite(distances[target]):
            raise self._no_passage(start, goal)
        points = self._nodes_back(previous, source, target)
        points[0], points[-1] = ends
        return points

    def cheapest_ends(self, start: End, goal: End) -> tuple[tuple[float, float], tuple[float, float]]:
        """The start and goal the cheapest free path joins (`path`'s cost; one search from every start node):
        each end a point, kept, or a rectangle (x_min, x_max, y_min, y_max), in which the grid node with room for the
        narrowest tube that the cheapest path leaves from or arrives at is chosen."""
        index = np.arange(self.free.size).reshape(self.free.shape)
        chosen = [self._candidates(end, what) for end, what in ((start, 'start'), (goal, 'goal'))]
        cells = [np.argwhere(c)[0] for c, e in zip(chosen, (start, goal), strict=True) if len(e) == 2]
        points = tuple((int(i), int(j)) for i, j in cells)  # a point's node (room checked exactly) joins the graph
        distances, _, sources = csgraph.dijkstra(
            self._graph(points), directed=False, indices=index[chosen[0]], min_only=True, return_predecessors=True
        )
        targets = index[chosen[1]]
        if not np.isfinite(distances[targets]).any():
            first, last = (np.unravel_index(int(index[c][0]), self.free.shape) for c in chosen)
            raise self._no_passage((int(first[0]), int(first[1])), (int(last[0]), int(last[1])))
        target = int(targets[np.argmin(distances[targets])])
        ends = []
        for end, node in ((start, int(sources[target])), (goal, target)):
            i, j = np.unravel_index(node, self.free.shape)
            ends.append((float(end[0]), float(end[1])) if len(end) == 2 else (float(self.x[i]), float(self.y[j])))
        return ends[0], ends[1]

    def _candidates(self, end: End, what: str) -> NDArray[np.bool_]:
        """The nodes an end may be: a point's own node, or the free nodes inside a rectangle."""
        if len(end) == 2:
            mask = np.zeros(self.free.shape, dtype=bool)
            mask[self.node((end[0], end[1]), what)] = True
            return mask
        return self._in_box((end[0], end[1], end[2], end[3]), what)

    def _in_box(self, box: Box, what: str) -> NDArray[np.bool_]:
        """The free nodes inside a rectangle (x_min, x_max, y_min, y_max); none: a TubeGenerationError."""
        x0, x1, y0, y1 = box
        inside = ((self.x >= x0) & (self.x <= x1))[:, None] & ((self.y >= y0) & (self.y <= y1))[None, :]
        chosen: NDArray[np.bool_] = inside & self.free
        if not chosen.any():
            msg = (
                f'no point of the {what} region x {x0:g}..{x1:g}, y {y0:g}..{y1:g} m has room for the narrowest tube '
                f'({self.spec.room_m:.3f} m to every obstacle and the map edge); enlarge or move it.'
            )
            raise TubeGenerationError(msg)
        return chosen

    def _graph(self, ends: tuple[tuple[int, int], ...]) -> sparse.csr_matrix:
        """The 8-connected graph of the free nodes (and of ``ends``, whose room was checked exactly), each step
        weighted by its length times 1 + half_width_max / clearance (the path keeps to the middle of passages)."""
        spec, shape = self.spec, self.clear.shape
        free = self.free.copy()
        for end in ends:
            free[end] = True
        weight = 1.0 + spec.half_width_max_m / np.maximum(self.clear, 1e-9)
        index = np.arange(free.size).reshape(shape)
        rows, cols, costs = [], [], []
        for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1)):
            a = (slice(0, shape[0] - di), slice(max(0, -dj), shape[1] - max(0, dj)))
            b = (slice(di, shape[0]), slice(max(0, dj), shape[1] - max(0, -dj)))
            both = free[a] & free[b]
            step = spec.resolution_m * math.hypot(di, dj)
            rows.append(index[a][both])
            cols.append(index[b][both])
            costs.append(step * 0.5 * (weight[a][both] + weight[b][both]))
        return sparse.coo_matrix(
            (np.concatenate(costs), (np.concatenate(rows), np.concatenate(cols))), shape=(free.size, free.size)
        ).tocsr()

    def _nodes_back(self, previous: NDArray[np.intp], source: int, target: int) -> FloatArray:
        nodes = [target]
        while nodes[-1] != source:
            nodes.append(int(previous[nodes[-1]]))
        i, j = np.unravel_index(np.array(nodes[::-1]), self.clear.shape)
        return np.column_stack([self.x[i], self.y[j]])

    def _no_passage(self, start: tuple[int, int], goal: tuple[int, int]) -> TubeGenerationError:
        spec = self.spec
        widest, needed = self._widest_passage(start, goal), spec.room_m + 0.5 * math.sqrt(2.0) * spec.resolution_m
        msg = (
            f'no passage from the start to the goal leaves {needed:.3f} m of room (half_width_min_m, '
            f"margin_m, the certificate's share and half a grid diagonal); the widest has about {widest:.3f} m (to the grid's "
            f'{spec.resolution_m} m): lower half_width_min_m or margin_m, or move an obstacle.'
        )
        return TubeGenerationError(msg)

    def room(self, points: FloatArray) -> FloatArray:
        """A lower bound (k,) of the obstacles' clearance of (k, 2) points (the map's edge counts too, but for
        near the start and goal): the nearest node's less the distance to it (the clearance is 1-Lipschitz)."""
        h = self.spec.resolution_m
        i = np.minimum(np.maximum(np.rint((points[:, 0] - self.x[0]) / h).astype(int), 0), self.x.size - 1)
        j = np.minimum(np.maximum(np.rint((points[:, 1] - self.y[0]) / h).astype(int), 0), self.y.size - 1)
        room: FloatArray = self.clear[i, j] - np.hypot(points[:, 0] - self.x[i], points[:, 1] - self.y[j])
        return room

    def _widest_passage(self, start: tuple[int, int], goal: tuple[int, int]) -> float:
        """The largest clearance c for which start and goal are connected through nodes of clearance >= c (to
        the grid's resolution)."""
        levels = np.unique(self.clear[self.clear > 0.0])
        lo, hi = 0, levels.size - 1
        best = 0.0
        while lo <= hi:
            mid = (lo + hi) // 2
            labels, _ = ndimage.label(self.clear >= levels[mid], structure=np.ones((3, 3)))
            if labels[start] and labels[start] == labels[goal]:
                best, lo = float(levels[mid]), mid + 1
            else:
                hi = mid - 1
        return best


def _segment_room(a: FloatArray, b: FloatArray, grid: SearchGrid) -> float:
    """A lower bound of the clearance along the segment a-b (`_segment_rooms`)."""
    return float(_segment_rooms(a, b[None, :], grid)[0])


def _segment_rooms(a: FloatArray, ends: FloatArray, grid: SearchGrid) -> FloatArray:
    """Lower bounds (k,) of the clearance along the segments from a to each of (k, 2) ends: samples a fifth of the
    resolution apart (less half their spacing: the clearance is 1-Lipschitz), all segments' in one lookup."""
    d = ends - a
    lengths = np.hypot(d[:, 0], d[:, 1])
    n = np.maximum(2, np.ceil(lengths / (0.2 * grid.spec.resolution_m)).astype(int) + 1)
    first = np.concatenate([[0], np.cumsum(n)[:-1]])
    along = (np.arange(n.sum()) - np.repeat(first, n)) * np.repeat(1.0 / (n - 1), n)  # np.linspace(0, 1, n) each
    along[first + n - 1] = 1.0
    points = a + along[:, None] * np.repeat(d, n, axis=0)
    rooms: FloatArray = np.minimum.reduceat(grid.room(points), first) - 0.5 * lengths / (n - 1)
    return rooms


def centre_curve(path: FloatArray, grid: SearchGrid) -> tuple[FloatArray, ArcPath]:
    """The corners and the rounded centre curve of the path pulled straight or, when that one cannot be rounded,
    simplified; the first refusal when neither can."""
    spec = grid.spec
    head = [spec.start_m] if spec.start_heading_deg is not None else []
    tail = [spec.goal_m] if spec.goal_heading_deg is not None else []
    leads = ([(np.array(spec.start_m), path[0])] if head else []) + (
        [(path[-1], np.array(spec.goal_m))] if tail else []
    )
    for one, other in leads:
        if _segment_room(one, other, grid) < spec.room_m:
            msg = (
                f'the straight lead from ({one[0]:.3f}, {one[1]:.3f}) to ({other[0]:.3f}, {other[1]:.3f}) has too '
                'little room; shorten lead_m or turn the heading.'
            )
            raise TubeGenerationError(msg)
    refusals = []
    for corners_of in (_pulled_straight, _simplified):
        core = _pulled_straight(corners_of(path, grid)[::-1], grid)[::-1]  # and back: no short last hop
        corners = np.vstack([np.array(head).reshape(-1, 2), core, np.array(tail).reshape(-1, 2)])
        try:
            return corners, _rounded(corners, grid, (bool(head), bool(tail)))
        except TubeGenerationError as err:
            refusals.append(err)
    raise refusals[0]


def _pulled_straight(path: FloatArray, grid: SearchGrid) -> FloatArray:
    """The path's vertices with every vertex dropped whose neighbours see each other with the room kept: the
    straightest path, whose corners graze the obstacles."""
    kept = [0]
    while kept[-1] < len(path) - 1:
        i, j = kept[-1], kept[-1] + 1
        while j + 1 < len(path):  # the next _BATCH candidates at once; j stops before the first without room
            keeps = _segment_rooms(path[i], path[j + 1 : j + 1 + _BATCH], grid) >= grid.spec.room_m
            kept_too = keeps.size if keeps.all() else int(np.argmin(keeps))
            j += kept_too
            if kept_too < keeps.size:
                break
        kept.append(j)
    return path[kept]


def _simplified(path: FloatArray, grid: SearchGrid) -> FloatArray:
    """The path's vertices that a chord cannot replace (Ramer-Douglas-Peucker): a chord replaces the vertices
    between its ends when it keeps the tube's room and strays from them by at most half their spare room (their
    clearance beyond the tube's), or a grid cell. The corners left lie on the path, which keeps to the middle of
    passages, so the arcs that round them, cutting a corner by r (1 / cos(turn / 2) - 1), find room there; a chord
    pulled tight past an obstacle (the straightest path) leaves none."""
    room, h = grid.spec.room_m, grid.spec.resolution_m
    spare = grid.room(path) - room
    keep = {0, len(path) - 1}
    stack = [(0, len(path) - 1)]
    while stack:
        i, j = stack.pop()
        if j - i < 2:
            continue
        a, d = path[i], path[j] - path[i]
        inner = path[i + 1 : j] - a
        stray = np.abs(d[0] * inner[:, 1] - d[1] * inner[:, 0]) / max(float(np.hypot(*d)), 1e-12)
        tolerance = max(0.5 * float(spare[i : j + 1].min()), h)
        if stray.max() <= tolerance and _segment_room(path[i], path[j], grid) >= room:
            continue
        k = i + 1 + int(np.argmax(stray))
        keep.add(k)
        stack += [(i, k), (k, j)]
    return path[sorted(keep)]


def _rounded(corners: FloatArray, grid: SearchGrid, leads: tuple[bool, bool] = (False, False)) -> ArcPath:
    """Lines between the corners, each corner rounded by the largest arc that fits in its share of each
    neighbouring segment and keeps the room; refused below ``turn_radius_min_m``. A segment between two corners is
    shared in proportion to tan(turn / 2), what each corner's tangent needs for the same radius (so that both reach
    a radius when the segment allows it for both); the first and last segments serve one corner (0.9 of them, half
    of a straight lead: ``leads``)."""
    spec = grid.spec
    d = np.diff(corners, axis=0)
    lengths = np.hypot(d[:, 0], d[:, 1])
    headings = np.arctan2(d[:, 1], d[:, 0])
    turns = np.angle(np.exp(1j * np.diff(headings)))  # (-pi, pi]
    n_seg = lengths.size
    need = np.tan(0.5 * np.abs(turns))
    radii = np.zeros(turns.size)
    for k, turn in enumerate(turns):
        if abs(turn) < 1e-9:
            continue
        before = (0.5 if leads[0] else 0.9) if k == 0 else need[k] / (need[k - 1] + need[k])
        after = (0.5 if leads[1] else 0.9) if k + 1 == n_seg - 1 else need[k] / (need[k] + need[k + 1])
        tangent = min(before * lengths[k], after * lengths[k + 1])
        largest = tangent / math.tan(0.5 * abs(turn))  # what the neighbouring segments allow
        smallest = max(spec.turn_radius_min_m, 1e-6)
        candidates = [float(r) for r in largest * 0.8 ** np.arange(20) if r > smallest]
        candidates += [smallest] if largest >= smallest else []
        radius = next((r for r in candidates if _arc_keeps_room(corners[k + 1], headings[k], turn, r, grid)), None)
        if radius is None:
            x, y = corners[k + 1]
            why = (
                f'the neighbouring corners leave room for a radius of {largest:.3f} m at most'
                if largest < smallest
                else f"an arc of radius {smallest:.3f} m or more comes closer to an obstacle than the tube's room"
            )
            if abs(turn) > math.radians(179.0):  # tan(turn / 2) without bound: no arc at all
                why = 'the route turns back on itself there, which no arc rounds (a heading against the route?)'

            lead = (k == 0 and leads[0]) or (k == turns.size - 1 and leads[1])  # a lead's end: half the lead's
            fix = 'move the obstacles near it apart, or the start or goal'  # segment (2 lead_m) serves the arc
            if lead and largest < smallest and abs(turn) < math.radians(179.0):
                needed = smallest * math.tan(0.5 * abs(turn))  # this turn's; a longer lead moves the turn too
                fix = f'lengthen lead_m beyond {needed:.2f} m (or leave it out: it is fitted), or turn the heading'
            msg = (
                f'the turn of {math.degrees(abs(turn)):.0f} degrees at ({x:.3f}, {y:.3f}) cannot be rounded with '
                f'turn_radius_min_m = {spec.turn_radius_min_m}: {why}; {fix}.'
            )
            raise CornerError(msg, (float(x), float(y)))
        radii[k] = radius
    tangents = radii * np.tan(0.5 * np.abs(turns))
    pieces: list[ArcPiece] = []
    for k in range(n_seg):
        straight = lengths[k] - (tangents[k - 1] if k > 0 else 0.0) - (tangents[k] if k < turns.size else 0.0)
        if straight > 1e-9:
            pieces.append(ArcPiece(float(straight)))
        if k < turns.size and radii[k] > 0.0:
            pieces.append(ArcPiece(float(radii[k] * abs(turns[k])), radius_m=float(radii[k]), left=bool(turns[k] > 0)))
    return ArcPath(tuple(pieces), (float(corners[0, 0]), float(corners[0, 1])), float(headings[0]))


def _arc_keeps_room(corner: FloatArray, heading: float, turn: float, radius: float, grid: SearchGrid) -> bool:
    """Whether the arc rounding ``corner`` (entered at ``heading``, turning by ``turn``) keeps the room."""
    tangent = radius * math.tan(0.5 * abs(turn))
    entry = corner - tangent * np.array([math.cos(heading), math.sin(heading)])
    side = 1.0 if turn > 0 else -1.0
    normal = side * np.array([-math.sin(heading), math.cos(heading)])
    center = entry + radius * normal
    n = max(3, math.ceil(radius * abs(turn) / (0.2 * grid.spec.resolution_m)) + 1)
    angles = np.linspace(0.0, turn, n)
    start_angle = math.atan2(*(entry - center)[::-1])
    points = center + radius * np.column_stack([np.cos(start_angle + angles), np.sin(start_angle + angles)])
    spacing = radius * abs(turn) / (n - 1)
    return bool(grid.room(points).min() - 0.5 * spacing >= grid.spec.room_m)
