"""Occupancy images as obstacles: a map from SLAM or ROS ``map_server`` (a PNG or PGM image, or a ``.npy`` array,
with its resolution and origin), every occupied pixel a closed square; their exact clearance and inside test.

In a scene or map file's ``[obstacles]``:

    images = [{ file = "room.png", resolution_m = 0.05, origin_m = [-10.0, -5.0], occupied_thresh = 0.65 }]

``file`` is read relative to the scene file's folder (or absolute); ``occupied_thresh`` and ``free_thresh`` are
optional (0.65 and 0.196, as ``map_server``'s maps give them). The conventions are ROS ``map_server``'s
(``trinary`` mode, ``negate: 0``): ``origin_m`` is the lower-left corner of the bottom-left pixel, row 0 of the
image is its top (the largest y), column 0 its left (the smallest x), and a pixel is occupied where its darkness,
1 - its grey level in [0, 1], exceeds ``occupied_thresh``, free where it is below ``free_thresh``, and unknown
(never mapped: ``map_server``'s grey 205) otherwise (a colour pixel's grey level is the mean of its red, green and
blue; alpha is ignored; integer pixels are scaled by their type's largest value). A ``.npy`` file (``np.save``;
pickled data is refused) holds a 2-D array of occupancy probabilities in [0, 1], read with the same thresholds,
or of booleans (True: occupied; none unknown), in the same orientation (row 0 the top).

**Unknown cells are obstacles** unless the entry says ``unknown = "free"``: a tube is never certified through
space nobody mapped (an unmapped wall is still a wall). With ``unknown = "free"`` they count as free, and
``vtube tube generate`` says how much of the tube lies on them; the figures draw unknown cells either way.

Occupied pixel (row i, column j) of an image of H rows is the closed square [x0 + j r, x0 + (j + 1) r] x
[y0 + (H - 1 - i) r, y0 + (H - i) r]. `OccupancyImage.clearance` is the exact Euclidean distance to the
union of those squares (0 on or inside one), hence 1-Lipschitz like a disc's or polygon's clearance
(`vtube_planning.geometry.obstacles`); it searches only the squares of *boundary* pixels (occupied with a
free 4-neighbour, or on the image's border) near a point, through a k-d tree of their centres.
"""

from __future__ import annotations

import hashlib
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from vtube_planning._validate import is_positive, is_real
from vtube_planning.errors import SceneError

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

OCCUPIED_THRESH = 0.65
"""The default ``occupied_thresh`` (ROS ``map_server``'s)."""
FREE_THRESH = 0.196
"""The default ``free_thresh`` (the value of ROS maps' YAML files: ``map_server``'s unknown grey 205 is unknown)."""
UNKNOWN = ('occupied', 'free')
"""What an entry's ``unknown`` may say of the unknown cells; the first is the default."""

_KEYS = {'file', 'resolution_m', 'origin_m'}
_OPTIONAL = {'occupied_thresh', 'free_thresh', 'unknown'}
_FIRST_K = 16
"""Boundary centres asked of the k-d tree per point at first (doubled for the points that need more)."""


@dataclass(frozen=True)
class OccupancyImage:
    """An occupancy image (module doc): which pixels are occupied (rows, columns; row 0 the top), the pixel side
    and the lower-left corner of the bottom-left pixel, in metres.

    Two images are equal (and hash alike) when their occupied pixels, resolution and origin are; ``source`` (the
    file read, absolute; '' for an image made in code), the thresholds and ``unknown_cells`` only record where they
    came from. ``occupied`` holds the obstacles: the unknown cells (``unknown_cells``, None: none) among them
    unless ``unknown_free``.
    """

    occupied: BoolArray = field(compare=False, repr=False)
    resolution_m: float
    origin_m: tuple[float, float]
    source: str = field(default='', compare=False)
    occupied_thresh: float = field(default=OCCUPIED_THRESH, compare=False)
    free_thresh: float = field(default=FREE_THRESH, compare=False)
    unknown_cells: BoolArray | None = field(default=None, compare=False, repr=False)
    unknown_free: bool = field(default=False, compare=False)
    digest: str = field(init=False, default='')
    _grid: BoolArray = field(init=False, compare=False, repr=False)
    _lows: FloatArray = field(init=False, compare=False, repr=False)
    _highs: FloatArray = field(init=False, compare=False, repr=False)
    _tree: cKDTree | None = field(init=False, compare=False, repr=False)

    def __post_init__(self) -> None:
        where = f'occupancy image {self.source!r}' if self.source else 'an occupancy image'
        if not is_positive(self.resolution_m):
            msg = f'{where}: resolution_m (metres per pixel) must be a finite number > 0; got {self.resolution_m!r}.'
            raise SceneError(msg)
        origin = tuple(self.origin_m) if isinstance(self.origin_m, (list, tuple)) else ()
        if len(origin) != 2 or not all(is_real(v) for v in origin):
            msg = f'{where}: origin_m must be [x, y], two finite numbers (metres); got {self.origin_m!r}.'
            raise SceneError(msg)
        if not is_real(self.occupied_thresh) or not 0.0 <= self.occupied_thresh < 1.0:
            msg = (
                f'{where}: occupied_thresh must be a number in [0, 1) (map_server: 0.65); got {self.occupied_thresh!r}.'
            )
            raise SceneError(msg)
        occupied = np.asarray(self.occupied)
        if occupied.ndim != 2 or occupied.size == 0 or occupied.dtype != np.bool_:
            msg = f'{where}: the occupied pixels must be a non-empty 2-D boolean array; got shape {occupied.shape}.'
            raise SceneError(msg)
        occupied = occupied.copy()
        occupied.setflags(write=False)
        r, (x0, y0) = float(self.resolution_m), (float(origin[0]), float(origin[1]))
        grid = occupied[::-1]  # row k from the bottom: y in [y0 + k r, y0 + (k + 1) r]
        padded = np.pad(grid, 1)
        inner = padded[:-2, 1:-1] & padded[2:, 1:-1] & padded[1:-1, :-2] & padded[1:-1, 2:]
        k, j = np.nonzero(grid & ~inner)  # boundary pixels: a free 4-neighbour, or on the border (padding is free)
        lows = np.column_stack([x0 + j * r, y0 + k * r])
        highs = np.column_stack([x0 + (j + 1) * r, y0 + (k + 1) * r])
        digest = hashlib.sha256(repr(occupied.shape).encode() + np.packbits(occupied).tobytes()).hexdigest()
        for name, value in (
            ('occupied', occupied),
            ('resolution_m', r),
            ('origin_m', (x0, y0)),
            ('digest', digest),
            ('_grid', grid),
            ('_lows', lows),
            ('_highs', highs),
            ('_tree', cKDTree(0.5 * (lows + highs)) if len(lows) else None),
        ):
            object.__setattr__(self, name, value)

    @property
    def extent_m(self) -> tuple[float, float, float, float]:
        """x_min, x_max, y_min, y_max of the image (matplotlib's ``imshow`` extent)."""
        rows, cols = self.occupied.shape
        x0, y0 = self.origin_m
        return x0, x0 + cols * self.resolution_m, y0, y0 + rows * self.resolution_m

    def on_unknown(self, points_m: FloatArray) -> BoolArray:
        """Whether each of (k, 2) points lies in an unknown cell (the pixel holding it), (k,)."""
        p = np.asarray(points_m, dtype=float).reshape(-1, 2)
        if self.unknown_cells is None:
            return np.zeros(p.shape[0], dtype=bool)
        rows, cols = self.unknown_cells.shape
        with np.errstate(invalid='ignore'):
            j = np.floor((p[:, 0] - self.origin_m[0]) / self.resolution_m)
            k = np.floor((p[:, 1] - self.origin_m[1]) / self.resolution_m)
        valid = (j >= 0) & (j < cols) & (k >= 0) & (k < rows)
        jv, kv = np.where(valid, j, 0).astype(np.intp), np.where(valid, k, 0).astype(np.intp)
        found: BoolArray = valid & self.unknown_cells[::-1][kv, jv]
        return found

    def inside(self, points_m: FloatArray) -> BoolArray:
        """Whether each of (k, 2) points lies in a closed occupied square, (k,): the 3 x 3 pixels around it tested
        with the square's edges as `clearance` computes them (so inside exactly where the clearance is 0)."""
        p = np.asarray(points_m, dtype=float).reshape(-1, 2)
        r, (x0, y0) = self.resolution_m, self.origin_m
        rows, cols = self._grid.shape
        with np.errstate(invalid='ignore'):
            j0 = np.floor((p[:, 0] - x0) / r)
            k0 = np.floor((p[:, 1] - y0) / r)
        near = np.flatnonzero((j0 >= -1) & (j0 <= cols) & (k0 >= -1) & (k0 <= rows))
        hit = np.zeros(p.shape[0], dtype=bool)
        for dj in (-1, 0, 1):
            for dk in (-1, 0, 1):
                j, k = j0[near].astype(np.intp) + dj, k0[near].astype(np.intp) + dk
                valid = (j >= 0) & (j < cols) & (k >= 0) & (k < rows)
                jv, kv = np.where(valid, j, 0), np.where(valid, k, 0)
                x, y = p[near, 0], p[near, 1]
                within = (x0 + jv * r <= x) & (x <= x0 + (jv + 1) * r) & (y0 + kv * r <= y) & (y <= y0 + (kv + 1) * r)
                hit[near] |= valid & self._grid[kv, jv] & within
        return hit

    def clearance(self, points_m: FloatArray) -> FloatArray:
        """The exact distance (k,) of (k, 2) points to the occupied squares, 0 on or inside one; inf with none.

        Why the search finds the nearest square: for a point p outside them, its nearest point q of their union U
        lies on U's boundary, so points outside U come arbitrarily close to q: in a free pixel's square F or beyond
        the image's border. Beyond the border: q lies on the border, and so does the occupied pixel S holding q, a
        boundary pixel. In F: S and F (closed grid squares) share an edge, and S has a free 4-neighbour, or only
        the corner q, and then the two pixels at q beside both are 4-neighbours of S and of F: either one is free
        (S is a boundary pixel) or both are occupied, each with F as a free 4-neighbour (boundary pixels holding
        q). So the distance to U is the distance to the boundary pixels' squares. A square of side r with centre c
        lies between |p - c| - r sqrt(2) / 2 and |p - c| from p; so the nearest square S*, no farther than the
        square of the nearest centre (distance d1), has its centre within d1 + r sqrt(2) / 2, and the k nearest
        centres contain it once the k-th lies beyond that (or k is all of them): the exact box distance to each of
        those k squares, least, is the clearance."""
        p = np.asarray(points_m, dtype=float).reshape(-1, 2)
        out = np.full(p.shape[0], np.inf)
        if self._tree is None:
            return out
        inside = self.inside(p)
        out[inside] = 0.0
        pending = np.flatnonzero(~inside)
        total = len(self._lows)
        k = min(_FIRST_K, total)
        reach = 0.5 * math.sqrt(2.0) * self.resolution_m
        while pending.size:
            distances, index = self._tree.query(p[pending], k=k)
            distances, index = distances.reshape(pending.size, k), index.reshape(pending.size, k)
            q = p[pending][:, None, :]
            gap = np.maximum(np.maximum(self._lows[index] - q, 0.0), q - self._highs[index])  # (n, k, 2)
            nearest = np.hypot(gap[:, :, 0], gap[:, :, 1]).min(axis=1)
            done = np.full(pending.size, k == total) | (distances[:, -1] > distances[:, 0] + reach)
            out[pending[done]] = nearest[done]
            pending, k = pending[~done], min(2 * k, total)
        return out

    def meets_squares(self, centres_m: FloatArray, half_m: float) -> BoolArray:
        """Whether the closed square of half-side ``half_m`` around each of (k, 2) centres meets an occupied
        pixel, (k,), from a summed-area table (a hair generous at the edges: conservative for a search grid)."""
        c = np.asarray(centres_m, dtype=float).reshape(-1, 2)
        r, (x0, y0) = self.resolution_m, self.origin_m
        rows, cols = self._grid.shape
        slack = 1e-9 * max(1.0, half_m)

        def span(low: FloatArray, high: FloatArray, n: int) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
            # pixel m meets [low, high] when m r <= high and (m + 1) r >= low (in pixels from the origin)
            first = np.clip(np.ceil(low / r) - 1, 0, n).astype(np.intp)
            last = np.clip(np.floor(high / r), -1, n - 1).astype(np.intp)
            return first, last

        j_lo, j_hi = span(c[:, 0] - x0 - half_m - slack, c[:, 0] - x0 + half_m + slack, cols)
        k_lo, k_hi = span(c[:, 1] - y0 - half_m - slack, c[:, 1] - y0 + half_m + slack, rows)
        table = np.zeros((rows + 1, cols + 1), dtype=np.int64)
        table[1:, 1:] = self._grid.cumsum(axis=0).cumsum(axis=1)
        some = (j_lo <= j_hi) & (k_lo <= k_hi)
        j_hi, k_hi = np.maximum(j_hi, j_lo - 1), np.maximum(k_hi, k_lo - 1)
        count = table[k_hi + 1, j_hi + 1] - table[k_lo, j_hi + 1] - table[k_hi + 1, j_lo] + table[k_lo, j_lo]
        met: BoolArray = some & (count > 0)
        return met

    def entry(self, folder: Path | None = None) -> dict[str, Any]:
        """This image's entry in ``[obstacles] images``: ``file`` relative to ``folder`` when it can be (else
        absolute); [`SceneError`][vtube_planning.errors.SceneError] for an image made in code (it has no file)."""
        if not self.source:
            msg = 'an occupancy image made in code has no file to write; save it (np.save) and read it from there.'
            raise SceneError(msg)
        file = self.source
        if folder is not None:
            try:
                file = os.path.relpath(self.source, os.path.abspath(folder))
            except ValueError:  # another drive (Windows): absolute it stays
                file = self.source
        return {
            'file': Path(file).as_posix() if not os.path.isabs(file) else file,
            'resolution_m': self.resolution_m,
            'origin_m': list(self.origin_m),
            'occupied_thresh': self.occupied_thresh,
            'free_thresh': self.free_thresh,
            'unknown': UNKNOWN[self.unknown_free],
        }


def image_from_entry(entry: object, folder: Path | None = None) -> OccupancyImage:
    """The occupancy image of one entry of ``[obstacles] images`` (module doc), its ``file`` read relative to
    ``folder`` (the scene file's; the current folder without one); [`SceneError`][vtube_planning.errors.SceneError]
    names what is wrong."""
    if not isinstance(entry, Mapping) or not _KEYS <= set(entry) <= _KEYS | _OPTIONAL:
        msg = (
            f'each of [obstacles] images needs the keys {sorted(_KEYS)} (and optionally occupied_thresh); got '
            f'{entry!r}.'
        )
        raise SceneError(msg)
    file = entry['file']
    if not isinstance(file, str) or not file.strip():
        msg = f'[obstacles] images: file must be the path of a PNG/PGM image or a .npy array, a string; got {file!r}.'
        raise SceneError(msg)
    threshold = entry.get('occupied_thresh', OCCUPIED_THRESH)
    if not is_real(threshold) or not 0.0 <= threshold < 1.0:
        msg = f'[obstacles] images: occupied_thresh of {file!r} must be a number in [0, 1) (map_server: 0.65); got '
        msg += f'{threshold!r}.'
        raise SceneError(msg)
    free = entry.get('free_thresh', min(FREE_THRESH, threshold))
    if not is_real(free) or not 0.0 <= free <= threshold:
        msg = f'[obstacles] images: free_thresh of {file!r} must be a number in [0, occupied_thresh = {threshold}] '
        msg += f'(map_server: 0.196); got {free!r}.'
        raise SceneError(msg)
    unknown = entry.get('unknown', UNKNOWN[0])
    if unknown not in UNKNOWN:
        msg = f'[obstacles] images: unknown of {file!r} must be "occupied" (the default: never mapped is never free) '
        msg += f'or "free"; got {unknown!r}.'
        raise SceneError(msg)
    base = Path(folder) if folder is not None else Path()
    path = Path(os.path.abspath(base / file))
    origin = entry['origin_m']
    darkness = _darkness(path, file, base)
    occupied: BoolArray = darkness > threshold
    cells = ~occupied & ~(darkness < free)  # neither occupied nor free: never mapped
    return OccupancyImage(
        occupied | cells if unknown == 'occupied' else occupied,
        entry['resolution_m'],
        tuple(origin) if isinstance(origin, (list, tuple)) else origin,
        source=str(path),
        occupied_thresh=float(threshold),
        free_thresh=float(free),
        unknown_cells=cells if cells.any() else None,
        unknown_free=unknown == 'free',
    )


def _darkness(path: Path, file: str, folder: Path) -> FloatArray:
    """Each pixel's darkness (occupancy probability) of an image or ``.npy`` file (module doc); a boolean array's
    cells are 1 (occupied) or 0 (free)."""
    if not path.is_file():
        msg = (
            f'[obstacles] images: the file {str(path)!r} does not exist (file = {file!r} is read relative to the '
            f"scene file's folder {str(folder)!r}); correct the path or put the image there."
        )
        raise SceneError(msg)
    if path.suffix.lower() == '.npy':
        return _darkness_npy(path)
    import matplotlib.image

    try:
        pixels = np.asarray(matplotlib.image.imread(path))
    except (OSError, ValueError, SyntaxError) as err:
        msg = f'[obstacles] images: {str(path)!r} is not an image matplotlib can read ({err}); give a PNG or PGM.'
        raise SceneError(msg) from err
    scale = float(np.iinfo(pixels.dtype).max) if np.issubdtype(pixels.dtype, np.integer) else 1.0
    grey = pixels.astype(float) / scale
    if grey.ndim == 3 and grey.shape[2] in (1, 2):  # grey, grey and alpha
        grey = grey[:, :, 0]
    elif grey.ndim == 3 and grey.shape[2] in (3, 4):  # RGB, RGBA: the mean of red, green and blue
        grey = grey[:, :, :3].mean(axis=2)
    if grey.ndim != 2 or grey.size == 0:
        msg = f'[obstacles] images: {str(path)!r} has pixels of shape {pixels.shape}; give a grey or colour image.'
        raise SceneError(msg)
    darkness: FloatArray = 1.0 - grey
    return darkness


def _darkness_npy(path: Path) -> FloatArray:
    """The occupancy probabilities of a ``.npy`` array of them or of booleans (1.0: occupied, 0.0: free)."""
    try:
        array = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as err:
        why = 'holds pickled data, which is refused' if 'pickle' in str(err) else f'cannot be read ({err})'
        msg = (
            f'[obstacles] images: {str(path)!r} {why}; save a plain numeric or boolean array with np.save(path, array).'
        )
        raise SceneError(msg) from err
    if not isinstance(array, np.ndarray) or array.ndim != 2 or array.size == 0:
        shape = getattr(array, 'shape', type(array).__name__)
        msg = f'[obstacles] images: {str(path)!r} must hold a non-empty 2-D array (rows, columns); got {shape}.'
        raise SceneError(msg)
    if array.dtype == np.bool_:
        return array.astype(float)
    if not np.issubdtype(array.dtype, np.number) or np.iscomplexobj(array):
        msg = f'[obstacles] images: {str(path)!r} holds {array.dtype} values; give occupancy probabilities or booleans.'
        raise SceneError(msg)
    values = array.astype(float)
    if not np.all(np.isfinite(values) & (values >= 0.0) & (values <= 1.0)):
        msg = (
            f'[obstacles] images: {str(path)!r} must hold occupancy probabilities in [0, 1] (NaN and values outside '
            'refused; a ROS OccupancyGrid of 0..100 and -1: divide by 100 and give unknown cells a value).'
        )
        raise SceneError(msg)
    return values
