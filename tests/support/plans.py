"""The comparison of a banded plan with the cvxpy reference's, shared by the planner's tests."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.planning.plan import Plan

CERTIFICATE = 1e-8  # the bound for the banded planner


def assert_same_plan(banded: Plan, reference: Plan, *, density: bool = True) -> None:
    """Same objective to 1e-8 relative (the solvers' tolerances), same profiles, banded certified below 1e-8.

    The density is only weakly pinned (its term of (p1) is worth about 0.01 s), so the reference's own solver
    tolerance (1e-8 on the objective) leaves it accurate to about 1e-5: it is compared to 1e-4 of rho_max, and not
    at all (``density=False``) when its weight is zero and any feasible density is optimal.
    """
    assert banded.solved.formulation == 'banded' and reference.solved.formulation == 'cvxpy'
    j = reference.objective['total']
    assert banded.objective['total'] == pytest.approx(j, rel=1e-8)
    np.testing.assert_array_equal(banded.l_m, reference.l_m)
    np.testing.assert_allclose(banded.speed_mps, reference.speed_mps, rtol=1e-5)
    if density:
        rho_max = banded.swarm.rho_max_per_m2
        np.testing.assert_allclose(banded.density_per_m2, reference.density_per_m2, atol=1e-4 * rho_max)
    assert banded.max_violation <= CERTIFICATE
