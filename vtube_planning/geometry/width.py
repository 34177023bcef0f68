"""Half-width profile lambda(l) of a virtual tube, as an exact piecewise polynomial.

A profile starts at a half-width and is a sequence of parts along the arc length:

* ``constant``: lambda keeps its value;
* ``smooth``: lambda moves to ``to_m`` along the C^1 cubic smoothstep of ``docs/theory.md`` §2.3
  (lambda = (lambda_a - lambda_b) sigma(l, l_a, l_b) + lambda_b), flat at both ends;
* ``linear``: a trapezoidal ramp to ``to_m`` whose two corners are rounded by parabolic blends of length
  ``corner_m`` each, so that the profile stays C^1 (regularity condition R4, ``docs/theory.md`` §3.2). With
  ``corner_m = 0`` the ramp has kinks, which the tube's regularity check rejects.

Because every part is a polynomial, lambda'(l) and the cumulative area A(l) = integral of 2 lambda are exact.
Outside [0, L] the profile continues with its end values (the tube's straight extensions).

`first_narrowing` is the one detector of where a tube first narrows: on a profile's knots (the part ends,
`WidthProfile.knots`: every part is monotone between them) or on any half-width sampled along a tube (the sampled
tube a submission carries).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PPoly

from vtube_planning._validate import is_positive, is_real
from vtube_planning.errors import TubeError
from vtube_planning.geometry._roots import bracketed_newton

FloatArray = NDArray[np.float64]

PART_KINDS = ('constant', 'smooth', 'linear')
DEFAULT_CORNER_FRACTION = 0.1
"""Corner blend of a ``linear`` part, as a fraction of its length, when ``corner_m`` is not given."""


@dataclass(frozen=True)
class WidthPart:
    """One part of a width profile.

    Parameters
    ----------
    kind
        ``'constant'``, ``'smooth'`` or ``'linear'``.
    length_m
        Arc length covered by the part, > 0.
    to_m
        Half-width at the end of the part (``smooth`` and ``linear`` only), > 0.
    corner_m
        Length of each rounded corner of a ``linear`` part, ``0 <= 2 corner_m <= length_m``. Defaults to
        ``DEFAULT_CORNER_FRACTION * length_m``.
    """

    kind: str
    length_m: float
    to_m: float | None = None
    corner_m: float | None = None

    def __post_init__(self) -> None:
        if self.kind not in PART_KINDS:
            msg = f'width part kind must be one of {PART_KINDS}; got {self.kind!r}.'
            raise TubeError(msg)
        if not is_positive(self.length_m):
            msg = f'width part length_m must be finite and > 0; got {self.length_m!r}.'
            raise TubeError(msg)
        if self.kind == 'constant':
            if self.to_m is not None or self.corner_m is not None:
                msg = "a 'constant' width part takes only length_m; remove to_m / corner_m or use 'smooth'/'linear'."
                raise TubeError(msg)
            return
        if not is_real(self.to_m):
            msg = (
                f'a {self.kind!r} width part needs to_m, the half-width it ends at, a finite number; got {self.to_m!r}.'
            )
            raise TubeError(msg)
        if self.kind == 'smooth' and self.corner_m is not None:
            msg = "corner_m applies to 'linear' width parts only; remove it from the 'smooth' part."
            raise TubeError(msg)
        if self.kind == 'linear' and self.corner_m is not None:
            ok = is_real(self.corner_m) and 0.0 <= self.corner_m <= 0.5 * self.length_m
            if not ok:
                msg = (
                    f'corner_m of a linear width part must lie in [0, length_m/2] = [0, {0.5 * self.length_m:g}]; '
                    f'got {self.corner_m!r}.'
                )
                raise TubeError(msg)


@dataclass(frozen=True)
class WidthProfile:
    """Half-width lambda(l) on [0, L], built from a start value and parts.

    Parameters
    ----------
    start_m
        Half-width at l = 0, > 0.
    parts
        The parts in order along the tube; their lengths add up to the tube length.
    """

    start_m: float
    parts: tuple[WidthPart, ...]
    _poly: PPoly = field(init=False, repr=False, compare=False)
    _area: PPoly = field(init=False, repr=False, compare=False)
    _length_m: float = field(init=False, repr=False, compare=False)
    _end_m: float = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not is_positive(self.start_m):
            msg = f'width start_m (half-width at l = 0) must be finite and > 0; got {self.start_m!r}.'
            raise TubeError(msg)
        if not self.parts:
            msg = 'a width profile needs at least one part; add e.g. {kind = "constant", length_m = 10.0}.'
            raise TubeError(msg)
        object.__setattr__(self, 'parts', tuple(self.parts))
        end = 0.0
        for k, part in enumerate(self.parts):
            end += part.length_m
            if part.to_m is not None and part.to_m <= 0.0:
                msg = (
                    f'the half-width must stay > 0, but width part {k} ends at to_m = {part.to_m!r} m at '
                    f'l = {end:.3f} m; give every part a positive to_m.'
                )
                raise TubeError(msg)
        breaks, coefs = _polynomial_pieces(self.start_m, self.parts)
        poly = PPoly(np.array(coefs).T, np.array(breaks), extrapolate=False)
        object.__setattr__(self, '_poly', poly)
        object.__setattr__(self, '_area', poly.antiderivative())
        object.__setattr__(self, '_length_m', float(poly.x[-1]))  # both read by every area and value call
        object.__setattr__(self, '_end_m', float(poly(poly.x[-1])))

    @property
    def length_m(self) -> float:
        """Total arc length covered by the parts."""
        return self._length_m

    @property
    def knots(self) -> tuple[FloatArray, FloatArray]:
        """The arc lengths where the parts meet (0 and L included) and the half-width there: lambda is monotone
        between consecutive knots."""
        l_m, width = [0.0], [self.start_m]
        for part in self.parts:
            l_m.append(l_m[-1] + part.length_m)
            width.append(part.to_m if part.to_m is not None else width[-1])
        return np.array(l_m), np.array(width)

    @property
    def breakpoints(self) -> FloatArray:
        """Arc lengths where the polynomial pieces meet (including 0 and L)."""
        return np.array(self._poly.x, dtype=float)

    def value(self, l_m: FloatArray) -> FloatArray:
        """lambda(l) in m for a 1-D array of arc lengths (end values continue outside [0, L])."""
        return np.asarray(self._poly(np.minimum(np.maximum(l_m, 0.0), self._length_m)), dtype=float)

    def slope(self, l_m: FloatArray) -> FloatArray:
        """d lambda / dl (dimensionless) for a 1-D array of arc lengths (0 outside [0, L])."""
        l_m = np.asarray(l_m, dtype=float)
        inside = (l_m >= 0.0) & (l_m <= self.length_m)
        return np.where(inside, self._poly(np.clip(l_m, 0.0, self.length_m), 1), 0.0)

    def max_abs_slope(self) -> float:
        """max |d lambda / dl| over [0, L], exact: the slope of each polynomial piece (degree 3 at most) at both
        ends of the piece and where its own derivative vanishes."""
        slope = self._poly.derivative()
        widths = np.diff(slope.x)
        candidates = [np.abs(slope(slope.x))]
        if slope.c.shape[0] == 3:  # quadratic slopes: a x^2 + b x + c on [0, h], extremum at -b / 2a
            a, b = slope.c[0], slope.c[1]
            with np.errstate(divide='ignore', invalid='ignore'):
                vertex = np.where(a != 0.0, -b / (2.0 * a), -1.0)
            inside = (vertex > 0.0) & (vertex < widths)
            candidates.append(np.abs(slope(slope.x[:-1][inside] + vertex[inside])))
        elif slope.c.shape[0] > 3:
            msg = f'width pieces of degree {slope.c.shape[0]} are not expected (at most cubic).'
            raise TubeError(msg)
        return float(max(float(np.nanmax(c)) if c.size else 0.0 for c in candidates))

    def area(self, l_m: FloatArray) -> FloatArray:
        """Cumulative area A(l) = integral_0^l 2 lambda in m^2 (negative for l < 0, as the extension's area)."""
        l_m = np.asarray(l_m, dtype=float)
        length = self._length_m
        clipped = np.minimum(np.maximum(l_m, 0.0), length)
        inner: FloatArray = 2.0 * self._area(clipped)
        if not np.count_nonzero(l_m - clipped):  # all in [0, L] (a swarm in its tube): the extensions add zeros,
            return inner  # which change no bit of inner (A >= 0, and A(0) is +0.0, not -0.0)
        before = 2.0 * self.start_m * np.minimum(l_m, 0.0)
        after = 2.0 * self._end_m * np.maximum(l_m - length, 0.0)
        total: FloatArray = inner + before + after
        return total

    def area_inverse(self, a_m2: FloatArray) -> FloatArray:
        """The arc length l with A(l) = a, for a 1-D array of areas (any real a: A is a bijection of the line)."""
        a_m2 = np.asarray(a_m2, dtype=float)
        length, total = self.length_m, float(2.0 * self._area(self.length_m))
        out = np.where(a_m2 < 0.0, a_m2 / (2.0 * self.start_m), length + (a_m2 - total) / (2.0 * self.end_m))
        inner = np.flatnonzero((a_m2 >= 0.0) & (a_m2 <= total))
        if inner.size:
            knots = self._poly.x
            knot_area = 2.0 * self._area(knots)
            k = np.clip(np.searchsorted(knot_area, a_m2[inner], side='right') - 1, 0, knots.size - 2)
            target = a_m2[inner]

            def residual(x: FloatArray, idx: NDArray[np.intp]) -> tuple[FloatArray, FloatArray]:
                return 2.0 * self._area(x) - target[idx], 2.0 * self._poly(x)

            lo, hi = knots[k], knots[k + 1]
            guess = lo + (target - knot_area[k]) / (knot_area[k + 1] - knot_area[k]) * (hi - lo)
            out[inner] = bracketed_newton(residual, lo, hi, guess, xtol=1e-13 * max(1.0, length))
        return out

    @property
    def end_m(self) -> float:
        """Half-width at l = L."""
        return self._end_m

    def continuity_defects(self) -> list[tuple[float, float, float]]:
        """Jumps of lambda and lambda' at interior breakpoints, as ``(l, value jump, slope jump)``.

        Computed exactly from the coefficients of the pieces on either side.
        """
        coefs, knots = self._poly.c, self._poly.x
        defects = []
        for i in range(knots.size - 2):
            h = knots[i + 1] - knots[i]
            left_value = np.polyval(coefs[:, i], h)
            left_slope = np.polyval(np.polyder(coefs[:, i]), h)
            defects.append((float(knots[i + 1]), coefs[-1, i + 1] - left_value, coefs[-2, i + 1] - left_slope))
        return defects


def _polynomial_pieces(start_m: float, parts: tuple[WidthPart, ...]) -> tuple[list[float], list[list[float]]]:
    """Breakpoints and cubic coefficients (highest power first, local variable x = l - l_k) of the profile."""
    breaks = [0.0]
    coefs: list[list[float]] = []
    value = float(start_m)

    def add(length: float, c: list[float]) -> None:
        breaks.append(breaks[-1] + length)
        coefs.append(c)

    for part in parts:
        h = float(part.length_m)
        if part.kind == 'constant':
            add(h, [0.0, 0.0, 0.0, value])
            continue
        to = float(part.to_m)  # type: ignore[arg-type]
        delta = to - value
        if part.kind == 'smooth':
            add(h, [-2.0 * delta / h**3, 3.0 * delta / h**2, 0.0, value])
        else:
            corner = DEFAULT_CORNER_FRACTION * h if part.corner_m is None else float(part.corner_m)
            slope = delta / (h - corner)
            if corner > 0.0:
                add(corner, [0.0, slope / (2.0 * corner), 0.0, value])
            if h - 2.0 * corner > 0.0:
                add(h - 2.0 * corner, [0.0, 0.0, slope, value + 0.5 * slope * corner])
            if corner > 0.0:
                add(corner, [0.0, -slope / (2.0 * corner), slope, to - 0.5 * slope * corner])
        value = to
    return breaks, coefs


@dataclass(frozen=True)
class Narrowing:
    """Where a tube first narrows: from where its half-width starts falling to where it stops, and the half-widths
    there (m)."""

    start_m: float
    end_m: float
    half_width_before_m: float
    half_width_after_m: float

    @property
    def length_m(self) -> float:
        """Its length along the tube."""
        return self.end_m - self.start_m


def first_narrowing(l_m: FloatArray, half_width_m: FloatArray, tolerance_m: float = 1e-6) -> Narrowing | None:
    """The first run of steps over which ``half_width_m``, given at increasing arc lengths ``l_m`` and monotone
    between them, falls by more than ``tolerance_m`` each: from the step's first sample to the run's last (falling
    parts in a row are one narrowing). None where it never falls."""
    l_m, half_width_m = np.asarray(l_m, dtype=float), np.asarray(half_width_m, dtype=float)
    falling = np.diff(half_width_m) < -tolerance_m
    if not falling.any():
        return None
    first = int(np.argmax(falling))
    stop = first + int(np.argmin(falling[first:])) if not falling[first:].all() else falling.size
    return Narrowing(float(l_m[first]), float(l_m[stop]), float(half_width_m[first]), float(half_width_m[stop]))


def width_under(l_m: FloatArray, bound: FloatArray, slope_max: float, cells: int) -> WidthProfile:
    """A width profile over [l_m[0] = 0, l_m[-1]] that never exceeds ``bound`` (sampled at the increasing ``l_m``;
    the caller accounts for what lies between samples), with |d lambda / dl| <= ``slope_max``: ``cells`` ramps
    (``linear`` parts with corners of a tenth of their length) or constant parts between evenly spaced knots.

    A ramp lies between the values at its two knots, and a knot's value v_j is the bound's minimum over both parts
    that meet there, so the width stays under the bound. Values are then lowered, never raised, until neighbours
    differ by at most ``slope_max`` x 0.9 x the part's length (a ramp with corners c rises (length - c) x its
    steepest slope).
    """
    knots = np.linspace(0.0, float(l_m[-1]), cells + 1)
    part = float(knots[1] - knots[0])
    corner = DEFAULT_CORNER_FRACTION * part
    values = np.array([bound[(l_m >= a - part - 1e-12) & (l_m <= a + part + 1e-12)].min() for a in knots])
    rise = slope_max * (part - corner)
    for k in range(1, cells + 1):  # forward and backward: the largest values below these with rises <= rise
        values[k] = min(values[k], values[k - 1] + rise)
    for k in range(cells - 1, -1, -1):
        values[k] = min(values[k], values[k + 1] + rise)
    parts: list[WidthPart] = []
    for a, b in itertools.pairwise(values):
        if b != a:
            parts.append(WidthPart('linear', part, to_m=float(b), corner_m=corner))
        elif parts and parts[-1].kind == 'constant':
            parts[-1] = WidthPart('constant', parts[-1].length_m + part)
        else:
            parts.append(WidthPart('constant', part))
    return WidthProfile(float(values[0]), tuple(parts))
