"""The last-robot-out objective: the measured passing time (first robot in to last robot out) as the planner models it.

A swarm of N robots at density rho in a tube of half-width lambda covers the area N / rho spread over the width
2 lambda, so its extent along the tube is N / (2 lambda rho) and its half-extent N / (4 lambda rho). Its first robot
enters that half-extent over the entry speed before the centre does, and its last robot leaves that half-extent over
the exit speed after the centre does (``docs/theory.md`` §8.7):

    T_pass = integral of w dl  +  c_0 w_0 / rho_0  +  c_K w_K / rho_K,     c = N / (4 lambda),

with w = 1/v the slowness. The entry term is fixed by the initial values (p2), (p5); the exit term c w / rho is
bilinear in (w, 1/rho): its Hessian c [[0, -1/rho^2], [-1/rho^2, 2 w / rho^3]] is indefinite, so it is neither convex
nor concave. The planner majorises it at the previous iterate (w_bar, rho_bar) by a convex quadratic, its Taylor
expansion to first order plus the curvature diag(a, b) with diag(a, b) - H(w_bar, rho_bar) positive definite
(`ExitTerm.model`): the model lies above the term near the iterate, and the planner keeps a step only when it lies
above at the step (else the curvature grows and the step is solved again), so that the objective decreases
monotonically as in the convex-concave procedure. The constraints are not touched: every iterate is feasible, and the
certificate holds as for (p1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.params import SwarmParams

FloatArray = NDArray[np.float64]

CURVATURE_MARGIN = 0.25
"""The model's curvature along rho exceeds the term's, 2 c w / rho^3, by this fraction at the first try."""
GROWTH = 4.0
"""Factor by which the model's curvature grows when it does not lie above the term at the step."""
MAX_TRIES = 40
"""Curvature growths tried before the step is given up (the iterate is kept: it is feasible)."""
ROUNDING = 1e-12
"""Relative rounding allowed when checking that the model lies above the term."""


def half_extent_weight(tube: VirtualTube, swarm: SwarmParams, l_m: float) -> float:
    """c = N / (4 lambda(l)): the swarm's half-extent along the tube at l is c / rho (m), its time to pass c w / rho."""
    return swarm.n_robots / (4.0 * float(np.asarray(tube.half_width(np.array([l_m])))[0]))


def last_out_terms(
    tube: VirtualTube, swarm: SwarmParams, l_m: FloatArray, speed_mps: FloatArray, density: FloatArray
) -> dict[str, float]:
    """The two half-extent terms of T_pass for a plan (s): ``entry_s`` at its first grid point, ``exit_s`` at its last."""
    entry = half_extent_weight(tube, swarm, float(l_m[0])) / (float(speed_mps[0]) * float(density[0]))
    leave = half_extent_weight(tube, swarm, float(l_m[-1])) / (float(speed_mps[-1]) * float(density[-1]))
    return {'entry_s': entry, 'exit_s': leave}


@dataclass(frozen=True)
class QuadraticModel:
    """A convex quadratic in (w_K, rho_K) expanded: linear coefficients, curvatures (the diagonal of its Hessian) and
    constant, value = linear . x + 0.5 curvature . x^2 + constant."""

    linear: tuple[float, float]
    curvature: tuple[float, float]
    constant: float

    def value(self, w: float, rho: float) -> float:
        (lw, lr), (a, b) = self.linear, self.curvature
        return lw * w + lr * rho + 0.5 * (a * w * w + b * rho * rho) + self.constant


@dataclass(frozen=True)
class ExitTerm:
    """The exit term c w_K / rho_K of T_pass, and its convex majorant at an iterate."""

    weight: float
    """c = N / (4 lambda(L)), robots/m."""

    def value(self, w: float, rho: float) -> float:
        return self.weight * w / rho

    def gradient(self, w: float, rho: float) -> tuple[float, float]:
        return self.weight / rho, -self.weight * w / rho**2

    def model(self, w_bar: float, rho_bar: float, growth: float = 1.0) -> QuadraticModel:
        """The term's first-order expansion at (w_bar, rho_bar) plus 0.5 (a dw^2 + b drho^2), expanded.

        With H_rr = 2 c w / rho^3 and b = (1 + m) H_rr, a = c / (m w rho) (m = ``CURVATURE_MARGIN``), diag(a, b) - H
        has determinant c^2 / rho^4 > 0 at the iterate: the model lies above the term near it. ``growth`` >= 1
        scales both curvatures (a shorter, safer step)."""
        c, m = self.weight, CURVATURE_MARGIN
        g0 = self.value(w_bar, rho_bar)
        gw, gr = self.gradient(w_bar, rho_bar)
        a = growth * c / (m * w_bar * rho_bar)
        b = growth * (1.0 + m) * 2.0 * c * w_bar / rho_bar**3
        linear = (gw - a * w_bar, gr - b * rho_bar)
        constant = g0 - gw * w_bar - gr * rho_bar + 0.5 * (a * w_bar**2 + b * rho_bar**2)
        return QuadraticModel(linear, (a, b), constant)

    def lies_above(self, model: QuadraticModel, w: float, rho: float) -> bool:
        """Whether ``model`` is at least the term at (w, rho), to rounding."""
        term = self.value(w, rho)
        return term <= model.value(w, rho) + ROUNDING * max(1.0, abs(term))
