"""Width profiles: the smooth and linear parts in closed form, kinks and negative widths named."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.errors import TubeError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import Narrowing, WidthPart, WidthProfile, first_narrowing


def constant(length_m: float, half_width_m: float = 1.0) -> WidthProfile:
    return WidthProfile(half_width_m, (WidthPart('constant', length_m),))


def sigma(x: np.ndarray, d1: float, d2: float) -> np.ndarray:
    """The cubic smooth step of docs/theory.md §2.3 with its published coefficients (independent of width.py)."""
    den = (d1 - d2) ** 3
    a, b, c = -2.0 / den, 3.0 * (d1 + d2) / den, -6.0 * d1 * d2 / den
    d = d2**2 * (3.0 * d1 - d2) / den
    return np.where(x <= d1, 1.0, np.where(x >= d2, 0.0, a * x**3 + b * x**2 + c * x + d))


# ---------------------------------------------------------------------- width and area


def test_smooth_width_part_is_the_sigma_smoothstep() -> None:
    width = WidthProfile(
        4.0, (WidthPart('constant', 5.0), WidthPart('smooth', 6.0, to_m=1.5), WidthPart('constant', 4.0))
    )
    l = np.linspace(0.0, 15.0, 1001)
    expected = (4.0 - 1.5) * sigma(l, 5.0, 11.0) + 1.5
    np.testing.assert_allclose(width.value(l), expected, atol=1e-12)


def test_linear_width_part_is_a_rounded_trapezoid() -> None:
    width = WidthProfile(
        4.0, (WidthPart('constant', 5.0), WidthPart('linear', 10.0, to_m=1.0, corner_m=1.0), WidthPart('constant', 5.0))
    )
    slope = (1.0 - 4.0) / (10.0 - 1.0)
    np.testing.assert_allclose(width.slope(np.linspace(6.0, 14.0, 50)), slope, atol=1e-12)  # straight middle
    np.testing.assert_allclose(width.value(np.array([5.0, 15.0])), [4.0, 1.0], atol=1e-12)
    # C^1: one-sided difference quotients agree at every breakpoint
    h = 1e-7
    for b in width.breakpoints[1:-1]:
        left = (width.value(b) - width.value(b - h)) / h
        right = (width.value(b + h) - width.value(b)) / h
        assert abs(left - right) < 1e-5
    assert all(abs(jv) < 1e-12 and abs(js) < 1e-12 for _, jv, js in width.continuity_defects())


def test_width_with_kinks_is_not_c1_and_names_the_arc_length() -> None:
    width = WidthProfile(
        3.0, (WidthPart('constant', 5.0), WidthPart('linear', 4.0, to_m=1.0, corner_m=0.0), WidthPart('constant', 1.0))
    )
    with pytest.raises(TubeError, match=r'not C\^1 at l = 5\.000 m'):
        VirtualTube(ArcPath((ArcPiece(10.0),)), width)


def test_negative_width_names_the_arc_length() -> None:
    with pytest.raises(TubeError, match=r'to_m = -1.0 m at l = 9\.000 m'):
        WidthProfile(3.0, (WidthPart('constant', 5.0), WidthPart('smooth', 4.0, to_m=-1.0)))


@pytest.mark.parametrize('seed', range(5))
def test_the_width_under_a_bound_stays_under_it_with_its_slope_limited(seed: int) -> None:
    """Random rough bounds: the fitted width never exceeds the bound at any sample, its steepest slope (exact) is
    within the limit, and it loses little against the widest slope-limited function under the bound (the lower
    envelope min_k bound_k + slope |l - l_k|): at most a slope over two parts (0.75 m each)."""
    from vtube_planning.geometry.width import width_under

    rng = np.random.default_rng(seed)
    l_m = np.linspace(0.0, 30.0, 3001)
    bound = 1.5 + np.cumsum(rng.normal(0.0, 0.05, l_m.size)).clip(-1.0, 1.0)
    bound[1200:1800] = 2.0  # 6 m flat
    width = width_under(l_m, bound, 0.3, 40)
    assert width.length_m == pytest.approx(30.0, rel=1e-12)
    assert np.all(width.value(l_m) <= bound + 1e-12)
    assert width.max_abs_slope() <= 0.3 + 1e-12
    envelope = (bound[None, :] + 0.3 * np.abs(l_m[:, None] - l_m[None, :])).min(axis=1)
    assert np.all(width.value(l_m) >= envelope - 0.3 * 2 * 0.75 - 1e-9)


# ---------------------------------------------------------------------- the first narrowing


def test_the_first_narrowing_of_a_polyline_is_its_first_falling_run() -> None:
    l_m = np.linspace(0.0, 10.0, 101)
    # 1 m until l = 3, linear to 0.5 at l = 5, constant until 7, down to 0.25 at 8: the first run is [3, 5]
    width = np.interp(l_m, [0.0, 3.0, 5.0, 7.0, 8.0, 10.0], [1.0, 1.0, 0.5, 0.5, 0.25, 0.25])
    assert first_narrowing(l_m, width) == pytest.approx(Narrowing(3.0, 5.0, 1.0, 0.5))
    assert first_narrowing(l_m, width).length_m == pytest.approx(2.0)
    widening_first = np.interp(l_m, [0.0, 2.0, 4.0, 6.0, 10.0], [0.5, 0.8, 0.8, 0.6, 0.6])
    assert first_narrowing(l_m, widening_first) == pytest.approx(Narrowing(4.0, 6.0, 0.8, 0.6))  # not at entry


def test_the_narrowing_ends_where_the_samples_end_or_is_none() -> None:
    l_m = np.linspace(0.0, 1.0, 11)
    assert first_narrowing(l_m, 1.0 - 0.5 * l_m) == pytest.approx(Narrowing(0.0, 1.0, 1.0, 0.5))
    assert first_narrowing(l_m, 1.0 + l_m) is None
    wiggle = 1.0 + 1e-7 * np.cos(40.0 * l_m)  # falls, but by less than the tolerance per step
    assert first_narrowing(l_m, wiggle) is None
    assert first_narrowing(l_m, wiggle, tolerance_m=1e-9) is not None


def test_the_knots_of_a_profile_and_its_narrowing_from_them() -> None:
    profile = WidthProfile(
        0.5, (WidthPart('constant', 1.4), WidthPart('linear', 0.5, 0.25, 0.06), WidthPart('constant', 0.55))
    )
    l_m, width = profile.knots
    np.testing.assert_allclose(l_m, [0.0, 1.4, 1.9, 2.45])
    np.testing.assert_allclose(width, profile.value(l_m), atol=1e-15)  # the profile itself at its knots
    assert first_narrowing(l_m, width) == pytest.approx(Narrowing(1.4, 1.9, 0.5, 0.25))


def test_falling_parts_in_a_row_are_one_narrowing_and_samples_agree_with_the_knots() -> None:
    profile = WidthProfile(
        1.0,
        (
            WidthPart('constant', 2.0),
            WidthPart('smooth', 1.0, 0.8),
            WidthPart('linear', 2.0, 0.5),
            WidthPart('constant', 1.0),
            WidthPart('smooth', 1.0, 0.3),
        ),
    )
    exact = first_narrowing(*profile.knots)
    assert exact == pytest.approx(Narrowing(2.0, 5.0, 1.0, 0.5))
    tube = VirtualTube(ArcPath((ArcPiece(profile.length_m),)), profile)
    samples = tube.sampled(0.01)
    sampled = first_narrowing(samples.l_m, samples.half_width_m)
    spacing = float(np.diff(samples.l_m).max())
    # from the sample interval that holds the knot (a smoothstep leaves its flat start slowly: within a few samples)
    assert exact.start_m - spacing <= sampled.start_m <= exact.start_m + 5 * spacing
    assert abs(sampled.end_m - exact.end_m) <= spacing and sampled.half_width_after_m == pytest.approx(0.5)
