"""Projection: the clearance and the inside test from the tube coordinates alone."""

from __future__ import annotations

import numpy as np

from vtube_planning.onboard.projection import Projection


def projection(l_m: list[float], y_m: list[float], half_width_m: list[float], length_m: float = 10.0) -> Projection:
    n = len(l_m)
    tangent = np.tile([[1.0], [0.0]], n)
    return Projection(
        l_m=np.array(l_m),
        y_m=np.array(y_m),
        foot_m=np.vstack([l_m, np.zeros(n)]),
        tangent=tangent,
        normal=np.tile([[0.0], [1.0]], n),
        half_width_m=np.array(half_width_m),
        length_m=length_m,
        curvature_per_m=np.zeros(n),
    )


def test_clearance_is_the_half_width_less_the_offset_on_either_side() -> None:
    p = projection([1.0, 2.0, 3.0, 4.0], [0.5, -0.5, 1.5, -2.0], [1.0, 1.0, 1.0, 2.0])
    np.testing.assert_allclose(p.clearance_m, [0.5, 0.5, -0.5, 0.0])


def test_inside_needs_the_arc_length_in_the_tube_and_a_non_negative_clearance() -> None:
    p = projection([-0.1, 0.0, 5.0, 10.0, 10.1, 5.0, 5.0], [0, 0, 0.99, -1.0, 0, 1.01, -1.01], [1.0] * 7)
    assert p.inside.tolist() == [False, True, True, True, False, False, False]


def test_random_points_inside_agree_with_the_definition() -> None:
    rng = np.random.default_rng(0)
    l_m, y_m, lam = rng.uniform(-2, 12, 200), rng.uniform(-3, 3, 200), rng.uniform(0.5, 2.5, 200)
    p = projection(list(l_m), list(y_m), list(lam))
    expected = [(0 <= a <= 10) and abs(b) <= c for a, b, c in zip(l_m, y_m, lam, strict=True)]
    assert p.inside.tolist() == expected
