"""Classic barrier certificates against the official classic ones."""

from __future__ import annotations

import numpy as np
import pytest

import robotarium_exp.rps_classic.utilities.barrier_certificates as certificates


@pytest.mark.parametrize(
    'name',
    [n for n in certificates.__all__ if 'differential_drive' not in n],  # those solve exactly (quadprog)
)
def test_cvxopt_certificates_answer_as_the_official_classic_ones(name: str) -> None:
    """With the testbed's solver (the default), classic's cvxopt certificates give the PyPI simulator's answers."""
    official = pytest.importorskip('rps.utilities.barrier_certificates')  # PyPI robotarium-python-simulator
    theirs, ours = getattr(official, name)(), getattr(certificates, name)()
    unicycle = 'unicycle' in name
    rng = np.random.default_rng(6)
    worst = 0.0
    for _ in range(20):
        n = int(rng.integers(2, 10))
        x = np.vstack([rng.uniform(-0.6, 0.6, (2, n)), rng.uniform(-np.pi, np.pi, n)])
        if not unicycle:
            x = x[:2]
        u = np.vstack([rng.uniform(-0.2, 0.2, n), rng.uniform(-3, 3, n)]) if unicycle else rng.normal(0, 0.15, (2, n))
        worst = max(worst, float(np.abs(np.asarray(theirs(u.copy(), x.copy())) - ours(u, x)).max()))
    assert worst <= 1e-9


@pytest.mark.usefixtures('exact_qp')
def test_unicycle_certificate_maps_back_with_classic_clip() -> None:
    x = np.array([[0.0, 1.0], [0.0, 0.0], [0.0, np.pi / 2]])  # far apart: the certificate is inactive
    dxu = np.array([[0.05, 0.1], [3.4, -1.0]])  # at the points: speeds 0.177 and 0.112, under the limit
    out = certificates.create_unicycle_barrier_certificate()(dxu, x)
    np.testing.assert_allclose(out, [[0.05, 0.1], [np.pi, -1.0]], atol=1e-12)
