"""The virtual tube of the paper: a symmetric corridor around an arc-length parameterised centre curve.

A point of the plane is written ``p = gamma(l) + y n(l)`` with arc length l, unit tangent t, left normal n
(t rotated by +90 degrees) and signed lateral offset y; the tube is ``|y| <= lambda(l)``, ``0 <= l <= L``
(``docs/theory.md`` §3.1). Conventions:

* functions of arc length follow the path convention: scalar l -> (2,) or float, array (k,) -> (k, 2) or (k,);
* functions of robots follow the Robotarium convention: points (2, N), one robot per column.

Construction checks the regularity conditions of ``docs/theory.md`` §3.2 (`regularity`) and raises
[`TubeError`][vtube_planning.errors.TubeError] naming the arc length of the first violation.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from vtube_planning._validate import as_points
from vtube_planning.errors import ShapeError, TubeError
from vtube_planning.geometry._roots import bracketed_newton
from vtube_planning.geometry.centerline import CenterCurve
from vtube_planning.geometry.regularity import check_grid, check_regularity
from vtube_planning.geometry.warm_table import WarmTable
from vtube_planning.geometry.width import WidthProfile
from vtube_planning.onboard import Projection, SampledTube

FloatArray = NDArray[np.float64]

_LENGTH_RTOL = 1e-9
"""Relative tolerance between the centre line's length and the width profile's."""
_PROJECTION_XTOL = 1e-12
"""Absolute tolerance (m) of the arc length found by the projection's Newton iteration."""
_LEFT = np.array([-1.0, 1.0])
"""(t_x, t_y) reversed times this is the left normal (-t_y, t_x)."""
_LEFT_ROWS = _LEFT[:, None]
"""`_LEFT` for tangents (2, N), one per column."""
_WARM_NEWTON_STEPS = 6
"""Newton steps of [`VirtualTube.project_near`][vtube_planning.geometry.tube.VirtualTube.project_near] before a point
is projected globally (the first uses the frame the previous projection carries, each further one evaluates the centre
line's frame once)."""


@dataclass(frozen=True)
class VirtualTube:
    """A symmetric virtual tube: centre curve gamma(l), half-width lambda(l), l in [0, L].

    Parameters
    ----------
    center
        The centre curve, parameterised by arc length.
    width
        The half-width profile; it must cover exactly the centre curve's length.
    name
        Human-readable name (scene name), used in messages and figures.

    Raises
    ------
    TubeError
        If the lengths disagree or a regularity condition fails; the message names the arc length.
    """

    center: CenterCurve
    width: WidthProfile
    name: str = ''
    _samples: FloatArray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        length = self.center.length_m
        if abs(self.width.length_m - length) > _LENGTH_RTOL * max(1.0, length):
            msg = (
                f'tube {self.name!r}: the width parts cover {self.width.length_m:.6f} m but the centre line is '
                f'{length:.6f} m long; make the part lengths add up to the centre line length (omit length_m in '
                'the last part of a scene file to fill the rest).'
            )
            raise TubeError(msg)
        object.__setattr__(self, '_samples', _sample_grid(self))
        check_regularity(self.center, self.width, self._samples, self.name)

    # ------------------------------------------------------------------ evaluation along the arc length

    @property
    def length_m(self) -> float:
        """Arc length L of the centre curve in m."""
        return self.center.length_m

    def center_at(self, l_m: ArrayLike) -> FloatArray:
        """Centre point gamma(l): scalar -> (2,), (k,) -> (k, 2)."""
        arr, scalar = _arc_lengths(l_m)
        return _shape_points(self.center.frame(arr)[0], scalar)

    def tangent(self, l_m: ArrayLike) -> FloatArray:
        """Unit tangent t(l): scalar -> (2,), (k,) -> (k, 2)."""
        arr, scalar = _arc_lengths(l_m)
        return _shape_points(self.center.frame(arr)[1], scalar)

    def normal(self, l_m: ArrayLike) -> FloatArray:
        """Left unit normal n(l) (t rotated by +90 degrees): scalar -> (2,), (k,) -> (k, 2)."""
        arr, scalar = _arc_lengths(l_m)
        return _shape_points(_left(self.center.frame(arr)[1]), scalar)

    def curvature(self, l_m: ArrayLike) -> FloatArray | float:
        """Signed curvature kappa(l) in 1/m (positive turning left): scalar -> float, (k,) -> (k,)."""
        arr, scalar = _arc_lengths(l_m)
        return _shape(self.center.frame(arr)[2], scalar)

    def curvature_radius(self, l_m: ArrayLike) -> FloatArray | float:
        """Curvature radius r_t = 1/|kappa| in m (inf on straight parts): scalar -> float, (k,) -> (k,)."""
        arr, scalar = _arc_lengths(l_m)
        kappa = np.abs(self.center.frame(arr)[2])
        with np.errstate(divide='ignore'):
            return _shape(np.where(kappa > 0.0, 1.0 / kappa, np.inf), scalar)

    def half_width(self, l_m: ArrayLike) -> FloatArray | float:
        """Half-width lambda(l) in m: scalar -> float, (k,) -> (k,)."""
        arr, scalar = _arc_lengths(l_m)
        return _shape(self.width.value(arr), scalar)

    def half_width_slope(self, l_m: ArrayLike) -> FloatArray | float:
        """d lambda / dl (dimensionless): scalar -> float, (k,) -> (k,)."""
        arr, scalar = _arc_lengths(l_m)
        return _shape(self.width.slope(arr), scalar)

    def boundaries(self, l_m: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Left and right boundary points gamma +/- lambda n: each scalar -> (2,), (k,) -> (k, 2)."""
        arr, scalar = _arc_lengths(l_m)
        pos, tan, _ = self.center.frame(arr)
        offset = self.width.value(arr)[:, None] * _left(tan)
        return _shape_points(pos + offset, scalar), _shape_points(pos - offset, scalar)

    def area(self, l_m: ArrayLike) -> FloatArray | float:
        """Cumulative area A(l) = integral_0^l 2 lambda in m^2 (exact for a symmetric tube, ``docs/theory.md`` §3.1)."""
        arr, scalar = _arc_lengths(l_m)
        return _shape(self.width.area(arr), scalar)

    def area_inverse(self, a_m2: ArrayLike) -> FloatArray | float:
        """Arc length l with A(l) = a (the inverse of [`area`][vtube_planning.geometry.tube.VirtualTube.area]): scalar
        -> float, (k,) -> (k,)."""
        arr, scalar = _arc_lengths(a_m2, what='area')
        return _shape(self.width.area_inverse(arr), scalar)

    # ------------------------------------------------------------------ points of the plane

    def project(self, points_m: ArrayLike) -> Projection:
        """Project points onto the centre curve: closest point, arc length, lateral offset.

        Parameters
        ----------
        points_m
            Points, shape (2, N) (one per column; a single point may be given as (2,)).

        Returns
        -------
        Projection
            Arc lengths, offsets and frames, arrays over the N points.

        Notes
        -----
        A k-d tree over a dense sampling of the curve gives the nearest sample, which brackets the closest point;
        a safeguarded Newton iteration on ``g(l) = (p - gamma(l)) . t(l) = 0`` (``g' = -(1 - kappa y)``) then
        converges to 1e-12 m. The result is the exact closest point wherever ``1 - kappa y > 0`` near it, which
        holds for every point of a regular tube and for all points closer to the curve than its curvature radius.
        """
        xy = as_points(points_m, allow_single=True)
        l_m = self._nearest_arc_lengths(xy.T)
        return self._projection(xy, l_m, *self.center.frame(l_m))

    def project_near(self, points_m: ArrayLike, near: Projection) -> Projection:
        """[`project`][vtube_planning.geometry.tube.VirtualTube.project], started from ``near``, a projection onto this
        tube of N points close to these (the previous control period's): its arc lengths, and the centre line's frame
        there, which it carries.

        Same result as [`project`][vtube_planning.geometry.tube.VirtualTube.project] (to about 1e-12 m), found without
        the global search for the points whose local answer is certainly the closest point of the whole curve; the
        others are projected globally.

        Notes
        -----
        From l_0 = ``near.l_m``, plain Newton steps on ``g(l) = (gamma(l) - p) . t(l)`` (``g' = 1 - kappa y``), at
        most `_WARM_NEWTON_STEPS`, until a step is below 1e-12 m; the answer is the last iterate, where the
        frame was evaluated. Its distance d = |p - gamma(l)| is then certified the global minimum by the table of
        `WarmTable` (sample s_i nearest to l, window W, bounds T_i and K_i): with q = |p - gamma(s_i)|,

        * every curve point with |l' - s_i| >= W is at least T_i - q from p (triangle inequality), so farther than
          d when ``d < T_i - q``;
        * on the window |l' - s_i| < W (which must contain l), ``|p - gamma(l')| < q + W``, so the distance's second
          derivative ``1 - kappa y >= 1 - K_i (q + W) > 0`` when ``K_i (q + W) < 1``: the distance is strictly
          convex there and its stationary point l is the window's only minimum.

        Both strict, so l is the unique closest point: where the centre curve comes back close to itself (or a
        robot jumped), the test fails and the point falls back to the global search instead of a wrong branch.
        """
        xy = as_points(points_m, allow_single=True)
        n = xy.shape[1]
        if near.l_m.shape != (n,):
            msg = f'near must project {n} points, one per point projected; it projects {near.l_m.size}.'
            raise ShapeError(msg)
        l_m, pos, tan, kappa, found, d = self._local_newton(xy, near)
        table = self._warm_table
        i = table.nearest_sample(l_m)
        window = table.window_m
        q = np.hypot(xy[0] - table.x_m[i], xy[1] - table.y_m[i])
        certain = d < table.far_m[i] - q
        certain &= table.kappa_max[i] * (q + window) < 1.0
        certain &= np.abs(l_m - table.l_m[i]) < window
        certain &= found
        if np.count_nonzero(certain) < n:  # a count: the cheapest test of a small boolean array
            redo = np.flatnonzero(~certain)
            l_m[redo] = self._nearest_arc_lengths(xy.T[redo])
            pos, tan, kappa = pos.copy(), tan.copy(), kappa.copy()  # they may be near's frame, which stays as it is
            pos[redo], tan[redo], kappa[redo] = self.center.frame(l_m[redo])
        return self._projection(xy, l_m, pos, tan, kappa)

    def _nearest_arc_lengths(self, xy: FloatArray) -> FloatArray:
        """The global search of [`project`][vtube_planning.geometry.tube.VirtualTube.project]: nearest sample, then
        bracketed Newton between its neighbours."""
        samples = self._samples
        _, k = self._sample_tree.query(xy)
        reach = 1e6 * max(1.0, self.length_m)  # the straight extensions: Newton is exact there in one step
        lo = np.where(k > 0, samples[np.maximum(k - 1, 0)], -reach)
        hi = np.where(k < samples.size - 1, samples[np.minimum(k + 1, samples.size - 1)], self.length_m + reach)

        def residual(l_m: FloatArray, idx: NDArray[np.intp]) -> tuple[FloatArray, FloatArray]:
            pos, tan, kappa = self.center.frame(l_m)
            d = xy[idx] - pos
            y = tan[:, 0] * d[:, 1] - tan[:, 1] * d[:, 0]
            return -np.einsum('ij,ij->i', d, tan), 1.0 - kappa * y

        return bracketed_newton(residual, lo, hi, samples[k], xtol=_PROJECTION_XTOL)

    def _local_newton(
        self, xy: FloatArray, near: Projection
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, NDArray[np.bool_], FloatArray]:
        """Newton on g(l) from ``near`` for (2, N) points: arc lengths, positions and tangents (N, 2) and curvatures
        there, which points converged (a step below 1e-12 m within `_WARM_NEWTON_STEPS` with g' > 0), and the
        points' distances to those positions.

        The first step uses the frame ``near`` carries (the frame at its arc lengths), the others evaluate it. Every
        point steps until all have converged or stopped: a small swarm's steps cost the number of numpy calls, which
        following only the unconverged points would add to (a converged point's further steps are below 1e-12 m). A
        point where g' <= 0 stops with the step NaN: its arc length stays NaN, which no comparison takes for a step
        below 1e-12 m or above it, so it neither converges nor keeps the others going, and is projected globally."""
        n = xy.shape[1]
        x, y = xy[0], xy[1]
        l_m, kappa = near.l_m.copy(), near.curvature_per_m.copy()  # copies: returned, and may be written to
        pos, tan = near.foot_m.T, near.tangent.T
        for k in range(_WARM_NEWTON_STEPS):
            dx, dy = x - pos[:, 0], y - pos[:, 1]
            tx, ty = tan[:, 0], tan[:, 1]
            slope = 1.0 - kappa * (tx * dy - ty * dx)
            step = np.divide(dx * tx + dy * ty, slope, out=np.full(n, np.nan), where=slope > 0.0)
            size = np.abs(step)
            if k == _WARM_NEWTON_STEPS - 1 or not np.count_nonzero(size > _PROJECTION_XTOL):  # NaN is not > either
                break
            l_m += step
            pos, tan, kappa = self.center.frame(l_m)
        return l_m, pos, tan, kappa, size <= _PROJECTION_XTOL, np.hypot(dx, dy)

    def _projection(
        self, xy: FloatArray, l_m: FloatArray, pos: FloatArray, tan: FloatArray, kappa: FloatArray
    ) -> Projection:
        """The projection of (2, N) points ``xy`` with feet at arc lengths ``l_m``, positions and tangents (N, 2) and
        curvatures (N,) there."""
        foot, tangent = pos.T.copy(), tan.T.copy()
        normal = tangent[::-1] * _LEFT_ROWS
        return Projection(
            l_m=l_m,
            y_m=np.einsum('ji,ji->i', xy - foot, normal),  # the same sums as over (N, 2) rows, bit for bit
            foot_m=foot,
            tangent=tangent,
            normal=normal,
            half_width_m=self.width.value(l_m),
            length_m=self.length_m,
            curvature_per_m=kappa,
        )

    @cached_property
    def _warm_table(self) -> WarmTable:
        return WarmTable.of(self.center, self.width, self._samples, self._sample_tree)

    def fingerprint(self) -> str:
        """A hash of the tube's geometry (centre line and half-width at 2001 arc lengths, to 1e-9 m).

        Equal tubes built differently (a copied scene file) share it; plans record it (``Plan.tube_hash``).
        """
        return self._fingerprint

    @cached_property
    def _fingerprint(self) -> str:
        l_m = np.linspace(0.0, self.length_m, 2001)
        table = np.vstack([self.center_at(l_m).T, self.width.value(l_m)[None, :]])
        return hashlib.sha256((np.round(table, 9) + 0.0).tobytes()).hexdigest()[:16]  # + 0.0: no -0.0

    def sampled(self, spacing_m: float = 0.01) -> SampledTube:
        """The tube as samples at most ``spacing_m`` apart (what a submission carries); see
        [`SampledTube`][vtube_planning.onboard.sampled_tube.SampledTube]."""
        if not spacing_m > 0.0:
            msg = f'sample spacing must be > 0; got {spacing_m!r}.'
            raise TubeError(msg)
        l_m = np.linspace(0.0, self.length_m, max(2, math.ceil(self.length_m / spacing_m) + 1))
        return SampledTube(l_m, self.center_at(l_m).T, self.width.value(l_m), self.width.area(l_m))

    @cached_property
    def _sample_tree(self) -> cKDTree:
        return cKDTree(self.center.frame(self._samples)[0])

    # ------------------------------------------------------------------ summary

    def summary(self) -> dict[str, float]:
        """Length, half-width range, smallest curvature radius, largest lambda |kappa| and area (SI units)."""
        grid = check_grid(self.center, self.width, self._samples)
        lam = self.width.value(grid)
        kappa = np.abs(self.center.frame(grid)[2])
        kmax = float(kappa.max())
        return {
            'length_m': self.length_m,
            'half_width_min_m': float(lam.min()),
            'half_width_max_m': float(lam.max()),
            'curvature_radius_min_m': math.inf if kmax == 0.0 else 1.0 / kmax,
            'lambda_kappa_max': float((lam * kappa).max()),
            'area_m2': float(self.width.area(np.array([self.length_m]))[0]),
        }


# ---------------------------------------------------------------------- helpers


def _arc_lengths(values: ArrayLike, what: str = 'arc length') -> tuple[FloatArray, bool]:
    arr = np.asarray(values, dtype=float)
    if arr.ndim > 1:
        msg = f'{what} must be a scalar or a 1-D array of shape (k,); got shape {arr.shape}.'
        raise ShapeError(msg)
    if np.count_nonzero(np.isfinite(arr)) < arr.size:  # a count: the cheapest test of a small boolean array
        msg = f'{what} must be finite; got {arr[~np.isfinite(arr)][:3].tolist()}.'
        raise ShapeError(msg)
    return np.atleast_1d(arr), arr.ndim == 0


def _shape(values: FloatArray, scalar: bool) -> FloatArray | float:
    if not scalar:
        return values
    return values[0] if values.ndim > 1 else float(values[0])


def _shape_points(points: FloatArray, scalar: bool) -> FloatArray:
    """(k, 2) points as returned: the single point (2,) for a scalar arc length, else all of them."""
    return points[0] if scalar else points


def _left(tangent: FloatArray) -> FloatArray:
    """Rotate (k, 2) unit vectors by +90 degrees."""
    rotated: FloatArray = tangent[:, ::-1] * _LEFT
    return rotated


def _sample_grid(tube: VirtualTube) -> FloatArray:
    """Arc lengths of the projection's k-d tree: finer than a quarter of the half-width and of r_t."""
    length = tube.length_m
    coarse = np.linspace(0.0, length, 2001)
    lam_min = float(tube.width.value(coarse).min())
    kappa_max = float(np.abs(tube.center.frame(coarse)[2]).max())
    spacing = min(0.25 * lam_min, length / 16.0)
    if kappa_max > 0.0:
        spacing = min(spacing, 0.125 / kappa_max)
    spacing = max(spacing, length / 200_000)
    n = math.ceil(length / spacing) + 1
    return np.unique(np.concatenate([np.linspace(0.0, length, n), tube.center.breakpoints]))
