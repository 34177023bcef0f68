"""Classic robust certificates (barrier_certificates2)."""

from __future__ import annotations

import numpy as np
import pytest

import robotarium_exp.rps_classic.utilities.barrier_certificates as certificates
from robotarium_exp.rps_classic.utilities.barrier_certificates2 import create_robust_barriers


@pytest.mark.usefixtures('exact_qp')
def test_certificate2_uses_the_unsafe_gain_inside_the_radius() -> None:
    x = np.array([[0.0, 0.1], [0.0, 0.0]])  # 0.1 m apart, inside 0.17 m: h < 0
    request = np.array([[0.2, 0.0], [0.0, 0.0]])  # robot 0 drives into robot 1
    safe = certificates.create_single_integrator_barrier_certificate2(barrier_gain=100, unsafe_barrier_gain=1e3)(
        request, x
    )
    row = np.array([0.2, 0.0, -0.2, 0.0])  # -2 (x_0 - x_1) . (u_0 - u_1) <= gain h^3
    bound = 1e3 * (0.1**2 - 0.17**2) ** 3
    u_hat = request.reshape(-1, order='F')
    expected = u_hat - max(0.0, row @ u_hat - bound) / (row @ row) * row  # projection onto one half-space
    np.testing.assert_allclose(safe.reshape(-1, order='F'), expected, atol=1e-9)
    plain = certificates.create_single_integrator_barrier_certificate(barrier_gain=100)(request, x)
    assert not np.allclose(plain, safe)


def test_robust_certificate_keeps_its_constraints() -> None:
    rng = np.random.default_rng(3)
    x = np.vstack([rng.uniform(-0.4, 0.4, (2, 6)), rng.uniform(-np.pi, np.pi, 6)])
    dxu = np.vstack([rng.uniform(-0.2, 0.2, 6), rng.uniform(-2, 2, 6)])
    for certificate in (
        create_robust_barriers(),
        certificates.create_unicycle_differential_drive_barrier_certificate_with_boundary(),
    ):
        out = certificate(dxu, x)
        wheels = np.vstack([out[0] / 0.008 - out[1] * 0.105 / 0.032, out[0] / 0.008 + out[1] * 0.105 / 0.032]) / 2
        assert np.abs(wheels).max() <= 12.5 + 1e-6
        assert certificate.stats.solves == 1 and certificate.stats.failures == 0
    calm = np.zeros((2, 6))
    far = np.vstack([np.linspace(-1.2, 1.2, 6), np.zeros(6), np.zeros(6)])
    np.testing.assert_array_equal(create_robust_barriers()(calm, far), calm)


def test_robust_barriers_fail_where_classics_quadprog_and_sizes_fail() -> None:
    """Infeasible (wheels limited to 1 rad/s cannot keep two robots 0.2 m apart from closing in): quadprog's error;
    a projection distance of 0 makes the objective singular; a size classic cannot allocate fails at creation."""
    dxu, x = np.array([[0.1, 0.1], [0.0, 0.5]]), np.array([[0.0, 0.2], [0.0, 0.0], [0.0, 3.1]])
    with pytest.raises(ValueError, match='^constraints are inconsistent, no solution$'):
        create_robust_barriers(wheel_vel_limit=1)(dxu, x, np.empty(0))
    with pytest.raises(ValueError, match='^matrix G is not positive definite$'):
        create_robust_barriers(projection_distance=0)(dxu, x, np.empty(0))
    with pytest.raises(ValueError, match='negative dimensions are not allowed'):
        create_robust_barriers(max_num_robots=-1)
    with pytest.raises(TypeError, match="bad operand type for unary -: 'str'"):
        create_robust_barriers(gamma='a')(dxu, x, np.empty(0))  # type: ignore[arg-type]
    assert create_robust_barriers()(dxu, x, np.empty(0)).shape == (2, 2)
