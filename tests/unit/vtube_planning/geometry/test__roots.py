"""bracketed_newton: roots of increasing functions, vectorised, safeguarded by bisection."""

from __future__ import annotations

import numpy as np

from vtube_planning.geometry._roots import bracketed_newton


def test_cube_roots_of_random_numbers() -> None:
    """x^3 - c = 0 on [0, 3]: the roots are c^(1/3)."""
    rng = np.random.default_rng(2)
    c = rng.uniform(0.0, 20.0, 100)
    roots = bracketed_newton(
        lambda x, idx: (x**3 - c[idx], 3 * x**2), np.zeros(100), np.full(100, 3.0), np.full(100, 1.5), xtol=1e-12
    )
    np.testing.assert_allclose(roots, np.cbrt(c), rtol=0, atol=1e-10)


def test_a_zero_derivative_falls_back_to_bisection_and_stays_in_the_bracket() -> None:
    """x^3 - 1 started at x = 0, where f' = 0: Newton alone divides by zero; the answer is still 1."""
    seen: list[float] = []

    def fun(x, idx):
        seen.extend(x.tolist())
        return x**3 - 1.0, 3 * x**2

    root = bracketed_newton(fun, np.array([-2.0]), np.array([2.0]), np.array([0.0]), xtol=1e-13)
    assert abs(root[0] - 1.0) < 1e-12
    assert min(seen) >= -2.0 and max(seen) <= 2.0


def test_a_wrong_derivative_still_converges() -> None:
    """f = atan(x - 0.3) with a derivative 100x too small: Newton overshoots the bracket, bisection takes over."""
    root = bracketed_newton(
        lambda x, idx: (np.arctan(x - 0.3), 0.01 / (1 + (x - 0.3) ** 2)),
        np.array([-10.0]),
        np.array([10.0]),
        np.array([9.0]),
        xtol=1e-12,
        max_iter=200,
    )
    assert abs(root[0] - 0.3) < 1e-11


def test_only_unconverged_equations_are_evaluated_and_an_exact_guess_is_kept() -> None:
    calls: list[list[int]] = []

    def fun(x, idx):
        calls.append(idx.tolist())
        target = np.array([0.5, 2.0])[idx]
        return x - target, np.ones_like(x)

    roots = bracketed_newton(fun, np.zeros(2), np.full(2, 4.0), np.array([0.5, 3.0]), xtol=1e-12)
    np.testing.assert_allclose(roots, [0.5, 2.0])
    assert calls[0] == [0, 1] and all(c == [1] for c in calls[1:])  # equation 0 was solved by its guess


def test_guesses_outside_the_bracket_are_clipped_into_it() -> None:
    first: list[float] = []

    def fun(x, idx):
        first.append(float(x[0]))
        return x - 1.0, np.ones_like(x)

    assert bracketed_newton(fun, np.array([0.0]), np.array([2.0]), np.array([7.0]), xtol=1e-12)[0] == 1.0
    assert first[0] == 2.0
