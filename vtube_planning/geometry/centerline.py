"""Centre curves gamma(l) of virtual tubes, parameterised by true arc length l in [0, L].

Two constructions share one interface ([`CenterCurve`][vtube_planning.geometry.centerline.CenterCurve]):

* [`ArcPath`][vtube_planning.geometry.centerline.ArcPath]: straight segments and circular arcs, evaluated in closed
form (exact);
* [`SplineCurve`][vtube_planning.geometry.centerline.SplineCurve]: a natural cubic spline through waypoints,
re-parameterised by its true arc length
  (Gauss-Legendre quadrature of |gamma'(u)| and a Hermite inverse with exact slopes), not by chord length.

Outside [0, L] every curve continues along its end tangents as straight rays with zero curvature: robots waiting
before the entrance or leaving past the exit still have a well-defined arc length, tangent and lateral offset.
Arrays of arc length are 1-D; positions come back as (k, 2), one row per arc length (path convention).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicHermiteSpline, CubicSpline

from vtube_planning._validate import is_positive
from vtube_planning.errors import TubeError

FloatArray = NDArray[np.float64]


class CenterCurve(ABC):
    """An arc-length parameterised plane curve with straight extensions beyond its ends."""

    @property
    @abstractmethod
    def length_m(self) -> float:
        """Arc length L of the curve in m."""

    @property
    @abstractmethod
    def breakpoints(self) -> FloatArray:
        """Arc lengths (including 0 and L) between which the curvature is smooth."""

    @abstractmethod
    def frame(self, l_m: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Position (k, 2), unit tangent (k, 2) and signed curvature (k,) for any real arc lengths (k,).

        Beyond the ends the curve is the straight continuation along the end tangent, with zero curvature.
        """


@dataclass(frozen=True)
class ArcPiece:
    """A straight segment (``radius_m`` None) or a circular arc of a
    [`ArcPath`][vtube_planning.geometry.centerline.ArcPath].

    Parameters
    ----------
    length_m
        Arc length of the piece, > 0.
    radius_m
        Radius of the arc, > 0; None for a straight segment.
    left
        Direction of the turn of an arc: True turns left (counter-clockwise, positive curvature).
    """

    length_m: float
    radius_m: float | None = None
    left: bool = True

    def __post_init__(self) -> None:
        if not is_positive(self.length_m):
            msg = f'a centre-line piece needs length_m finite and > 0; got {self.length_m!r}.'
            raise TubeError(msg)
        if self.radius_m is not None and not is_positive(self.radius_m):
            msg = f'an arc needs radius_m finite and > 0; got {self.radius_m!r}. Use a line for zero curvature.'
            raise TubeError(msg)

    @property
    def curvature(self) -> float:
        """Signed curvature 1/m (positive when turning left)."""
        if self.radius_m is None:
            return 0.0
        return (1.0 if self.left else -1.0) / self.radius_m


@dataclass(frozen=True)
class ArcPath(CenterCurve):
    """A centre curve made of straight segments and circular arcs, in closed form.

    Parameters
    ----------
    pieces
        The pieces in order; each starts where and in the direction the previous one ends (G1 continuity).
    start_xy_m
        Position of l = 0.
    heading_rad
        Direction of the tangent at l = 0, counter-clockwise from the x axis.
    """

    pieces: tuple[ArcPiece, ...]
    start_xy_m: tuple[float, float] = (0.0, 0.0)
    heading_rad: float = 0.0
    _starts: FloatArray = field(init=False, repr=False, compare=False)
    _joints: FloatArray = field(init=False, repr=False, compare=False)
    _s0: FloatArray = field(init=False, repr=False, compare=False)
    _kappa: FloatArray = field(init=False, repr=False, compare=False)
    _half_kappa: FloatArray = field(init=False, repr=False, compare=False)
    _theta0: FloatArray = field(init=False, repr=False, compare=False)
    _p0: FloatArray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not self.pieces:
            msg = 'a centre line needs at least one piece, e.g. {kind = "line", length_m = 10.0}.'
            raise TubeError(msg)
        object.__setattr__(self, 'pieces', tuple(self.pieces))
        start = np.asarray(self.start_xy_m, dtype=float)
        if start.shape != (2,) or not np.all(np.isfinite(start)) or not math.isfinite(self.heading_rad):
            msg = f'start_xy_m must be two finite numbers and heading finite; got {self.start_xy_m!r}, {self.heading_rad!r}.'
            raise TubeError(msg)
        lengths = np.array([p.length_m for p in self.pieces], dtype=float)
        kappa = np.array([p.curvature for p in self.pieces], dtype=float)
        starts = np.concatenate([[0.0], np.cumsum(lengths)])
        theta0 = self.heading_rad + np.concatenate([[0.0], np.cumsum(kappa * lengths)])

        def advance(p: FloatArray, s: float, k: int) -> FloatArray:  # along piece k from p, as frame() evaluates it
            point: FloatArray = _advance(p[None, :].copy(), np.array([s]), kappa[k], 0.5 * kappa[k], theta0[k])[0][0]
            return point

        p0 = [start]
        for k in range(len(self.pieces)):
            p0.append(advance(p0[-1], lengths[k], k))
        # frame()'s table: the pieces, and beyond both ends a straight ray of zero curvature along the end tangent,
        # starting where the pieces' own formula puts the end (the values of clipping l to [0, L], without clipping)
        last, s_end = len(self.pieces) - 1, starts[-1] - starts[-2]
        before, after = advance(start, 0.0, 0), advance(p0[last], s_end, last)
        table_kappa = np.concatenate([[0.0], kappa, [0.0]])
        object.__setattr__(self, '_starts', starts)
        # where each piece of the table begins (searched with side='right'): l = L still belongs to the last piece
        object.__setattr__(self, '_joints', np.concatenate([[0.0], starts[1:-1], [np.nextafter(starts[-1], np.inf)]]))
        object.__setattr__(self, '_s0', np.concatenate([[0.0], starts]))  # where s = 0 on each piece of the table
        object.__setattr__(self, '_kappa', table_kappa)
        object.__setattr__(self, '_half_kappa', 0.5 * table_kappa)
        theta_after = theta0[last] + kappa[last] * s_end
        object.__setattr__(self, '_theta0', np.concatenate([theta0[:1], theta0[:-1], [theta_after]]))
        object.__setattr__(self, '_p0', np.array([before, *p0[:-1], after]))

    @property
    def length_m(self) -> float:
        return float(self._starts[-1])

    @property
    def breakpoints(self) -> FloatArray:
        starts: FloatArray = self._starts.copy()
        return starts

    def frame(self, l_m: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        l_m = np.asarray(l_m, dtype=float)
        k = self._joints.searchsorted(l_m, side='right')  # the piece of the table, the rays included
        kappa = self._kappa[k]
        pos, tan = _advance(self._p0.take(k, axis=0), l_m - self._s0[k], kappa, self._half_kappa[k], self._theta0[k])
        return pos, tan, kappa


def _advance(
    p0: FloatArray, s: FloatArray, kappa: FloatArray | float, half_kappa: FloatArray | float, theta0: FloatArray | float
) -> tuple[FloatArray, FloatArray]:
    """Position (k, 2) and unit tangent (k, 2) after arc length s (k,) at constant curvature kappa (half_kappa =
    kappa / 2) from p0 (k, 2; overwritten: it becomes the position) at heading theta0 (exact for kappa = 0).

    The tangent's heading is theta0 + kappa s; the chord of an arc of length s has length s sinc(kappa s / 2) and
    direction theta0 + kappa s / 2.
    """
    theta = kappa * s
    theta += theta0
    half = half_kappa * s
    direction = half + theta0
    x = half  # pi (half / pi) with zeros as eps: np.sinc's argument written out, without its call overhead
    x /= np.pi
    x *= np.pi
    x[x == 0.0] = _SINC_EPS
    chord = np.sin(x)
    chord /= x
    chord *= s
    step = _unit(direction)
    step *= chord[:, None]
    p0 += step
    return p0, _unit(theta)


def _unit(theta: FloatArray) -> FloatArray:
    """(k, 2) unit vectors (cos theta, sin theta) of (k,) angles."""
    out = np.empty((theta.size, 2))
    np.cos(theta, out[:, 0])
    np.sin(theta, out[:, 1])
    return out


_SINC_EPS = float(np.finfo(float).eps)
"""What np.sinc puts in place of a zero argument."""


_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(8)
_SUBDIVISIONS = 64
"""Sub-intervals per spline interval for the arc-length table (relative arc-length error far below 1e-9)."""


@dataclass(frozen=True)
class SplineCurve(CenterCurve):
    """A natural cubic spline through waypoints, re-parameterised by true arc length.

    Parameters
    ----------
    waypoints_m
        Points the centre line passes through, shape (M, 2), M >= 2, consecutive points distinct. The first is
        l = 0, the last l = L. The spline's own parameter is the cumulative chord length; natural end conditions
        give zero curvature at both ends, so the straight extensions join with continuous curvature.
    """

    waypoints_m: tuple[tuple[float, float], ...]
    _spline: CubicSpline = field(init=False, repr=False, compare=False)
    _u_of_l: CubicHermiteSpline = field(init=False, repr=False, compare=False)
    _knot_l: FloatArray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        pts = np.asarray(self.waypoints_m, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2 or not np.all(np.isfinite(pts)):
            msg = f'waypoints must be at least two finite [x, y] pairs, shape (M, 2); got shape {pts.shape}.'
            raise TubeError(msg)
        object.__setattr__(self, 'waypoints_m', tuple(map(tuple, pts.tolist())))
        chords = np.hypot(*np.diff(pts, axis=0).T)
        if np.any(chords <= 1e-9 * max(1.0, chords.max())):
            k = int(np.argmin(chords))
            msg = f'waypoints {k} and {k + 1} coincide ({pts[k].tolist()}); remove the duplicate.'
            raise TubeError(msg)
        u_knots = np.concatenate([[0.0], np.cumsum(chords)])
        spline = CubicSpline(u_knots, pts, bc_type='natural')
        # dense table u -> l by Gauss-Legendre quadrature of the speed |gamma'(u)|
        u = np.linspace(u_knots[:-1], u_knots[1:], _SUBDIVISIONS + 1, axis=1)[:, :-1].ravel()
        u = np.append(u, u_knots[-1])
        a, b = u[:-1], u[1:]
        nodes = 0.5 * (b - a)[:, None] * _GAUSS_NODES + 0.5 * (a + b)[:, None]
        speed = np.hypot(*np.moveaxis(spline(nodes, 1), -1, 0))
        seg = 0.5 * (b - a) * (speed @ _GAUSS_WEIGHTS)
        l_table = np.concatenate([[0.0], np.cumsum(seg)])
        speed_table = np.hypot(*spline(u, 1).T)
        if np.any(speed_table <= 0.0):
            msg = 'the spline through the waypoints has a cusp (zero speed); space the waypoints more evenly.'
            raise TubeError(msg)
        object.__setattr__(self, '_spline', spline)
        object.__setattr__(self, '_u_of_l', CubicHermiteSpline(l_table, u, 1.0 / speed_table))
        object.__setattr__(self, '_knot_l', l_table[::_SUBDIVISIONS].copy())

    @property
    def length_m(self) -> float:
        return float(self._knot_l[-1])

    @property
    def breakpoints(self) -> FloatArray:
        """The arc lengths of the waypoints (the spline's curvature is C^0 there, smooth in between)."""
        knots: FloatArray = self._knot_l.copy()
        return knots

    def frame(self, l_m: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        l_m = np.asarray(l_m, dtype=float)
        clipped = np.minimum(np.maximum(l_m, 0.0), self.length_m)  # np.clip's values, at a fraction of its call cost
        u = self._u_of_l(clipped)
        d1 = self._spline(u, 1)
        d2 = self._spline(u, 2)
        speed = np.hypot(d1[:, 0], d1[:, 1])
        kappa = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / speed**3
        pos, tan = self._spline(u), d1 / speed[:, None]
        beyond = l_m - clipped  # the straight extensions
        pos += beyond[:, None] * tan  # in place: every fresh array of a large swarm costs its page faults
        return pos, tan, np.where(beyond != 0.0, 0.0, kappa)
