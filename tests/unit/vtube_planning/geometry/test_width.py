"""Width profiles: the smooth and linear parts in closed form, kinks and negative widths named."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.errors import TubeError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile


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
