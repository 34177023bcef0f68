"""Scalar functions of the law against docs/theory.md's published polynomial, values and finite differences."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.support.oracles import sigma_published
from vtube_planning.onboard.scalar import barrier_gain, saturate, sigma, smooth_saturation


def barrier_potential(x: float, offset: float, d1: float, d2: float, k: float, eps: float = 1e-6) -> float:
    """V = k sigma / ((1 + eps) x - offset s(x / offset)) written out from docs/theory.md §2.3-2.4."""
    x2 = 1 + eps / math.tan(math.radians(67.5))
    x1 = x2 - eps * math.sin(math.radians(45))
    u = x / offset
    s = u if u <= x1 else (1.0 if u >= x2 else (1 - eps) + math.sqrt(eps**2 - (u - x2) ** 2))
    return k * sigma_published(x, d1, d2) / ((1 + eps) * x - offset * s)


# ---------------------------------------------------------------------- building blocks


def test_sigma_matches_the_published_polynomial_and_its_band_edges() -> None:
    x = np.linspace(0.5, 1.5, 401)
    value, _ = sigma(x, 0.8, 1.2)
    np.testing.assert_allclose(value, [sigma_published(v, 0.8, 1.2) for v in x], atol=1e-12)
    edges, edge_slopes = sigma(np.array([0.8, 1.2]), 0.8, 1.2)
    np.testing.assert_allclose(edges, [1.0, 0.0])
    np.testing.assert_allclose(edge_slopes, [0.0, 0.0])
    h = 1e-6
    inner = x[(x > 0.81) & (x < 1.19)]
    fd = (sigma(inner + h, 0.8, 1.2)[0] - sigma(inner - h, 0.8, 1.2)[0]) / (2 * h)
    np.testing.assert_allclose(sigma(inner, 0.8, 1.2)[1], fd, atol=1e-7)
    assert np.all(np.diff(value) <= 0)  # monotone


@pytest.mark.parametrize('eps', [1e-6, 0.1, 0.3])
def test_smooth_saturation_is_c1_at_both_corners(eps: float) -> None:
    x2 = 1 + eps / math.tan(math.radians(67.5))
    x1 = x2 - eps * math.sin(math.radians(45))
    h = 1e-5 * eps  # small against the arc, which is about eps wide
    value, slope = smooth_saturation(np.array([x1 - h, x1 + h, x2 - h, x2 + h]), eps)
    np.testing.assert_allclose(value, [x1, x1, 1.0, 1.0], atol=2 * h)  # continuous: values differ by the step
    np.testing.assert_allclose(slope[[0, 1]], 1.0, atol=1e-3)
    np.testing.assert_allclose(slope[[2, 3]], 0.0, atol=2e-3)
    x = np.linspace(0.2, 1.6, 200)
    fd = (smooth_saturation(x + 1e-7, eps)[0] - smooth_saturation(x - 1e-7, eps)[0]) / 2e-7
    np.testing.assert_allclose(smooth_saturation(x, eps)[1], fd, atol=1e-5)


def test_barrier_potential_reproduces_theory_values() -> None:
    # docs/theory.md §2.4: r_s = 0.4, r_a = 0.8, k2 = 1, eps = 1e-6
    for x, expected in ((0.81, 99.8), (0.9, 8.4), (1.0, 2.5)):
        assert barrier_potential(x, 0.8, 0.8, 1.2, 1.0) == pytest.approx(expected, rel=0.01)
    assert barrier_potential(0.79, 0.8, 0.8, 1.2, 1.0) == pytest.approx(1.27e6, rel=0.01)
    assert barrier_potential(1.2, 0.8, 0.8, 1.2, 1.0) == 0.0


def test_barrier_gain_is_minus_the_potential_derivative() -> None:
    x = np.linspace(0.82, 1.25, 60)
    h = 1e-7
    fd = np.array(
        [
            -(barrier_potential(v + h, 0.8, 0.8, 1.2, 1.0) - barrier_potential(v - h, 0.8, 0.8, 1.2, 1.0)) / (2 * h)
            for v in x
        ]
    )
    np.testing.assert_allclose(barrier_gain(x, 0.8, 0.8, np.full(x.shape, 1.2), 1.0), fd, rtol=1e-5, atol=1e-6)
    assert np.all(barrier_gain(np.array([1.2, 2.0]), 0.8, 0.8, np.full(2, 1.2), 1.0) == 0.0)
    assert barrier_gain(np.array([0.5]), 0.8, 0.8, np.array([1.2]), 1.0)[0] > 1e6  # inside the safety distance


def test_saturate_rescales_radially_into_the_speed_band() -> None:
    u = np.array([[0.5, 3.0, 30.0, 0.0], [0.0, 4.0, 40.0, 0.0]])
    fallback = np.array([[1.0] * 4, [0.0] * 4])
    v = saturate(u, 2.0, 5.0, fallback)
    np.testing.assert_allclose(v.T, [[2.0, 0.0], [3.0, 4.0], [3.0, 4.0], [2.0, 0.0]])
    rng = np.random.default_rng(5)
    u = rng.normal(0.0, 4.0, (2, 30))
    with_zero = np.hstack([u, np.zeros((2, 1))])  # one zero command: the general path for every column
    fallback = np.vstack([np.ones(31), np.zeros(31)])
    np.testing.assert_array_equal(
        saturate(u, 2.0, 5.0, fallback[:, :30]), saturate(with_zero, 2.0, 5.0, fallback)[:, :30]
    )
