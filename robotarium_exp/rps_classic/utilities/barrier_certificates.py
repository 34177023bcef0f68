"""Classic ``rps.utilities.barrier_certificates``: every classic certificate, on V2's QP core.

Single integrators (``create_single_integrator_barrier_certificate``, ``..._with_boundary``): V2's classic-named
certificates (pairwise rows, optional walls, no speed polygon; the input is first scaled to the magnitude limit).
``..._certificate2`` uses ``unsafe_barrier_gain`` instead of ``barrier_gain`` on the rows of pairs already closer
than the safety radius (h < 0), so that they are pushed apart hard.

Unicycles (``create_unicycle_barrier_certificate``, ``..._with_boundary``, ``..._certificate2``): the matching
single-integrator certificate, with radius ``safety_radius + projection_distance`` and the default magnitude limit
(classic does not pass its ``magnitude_limit`` on), applied at the points ``projection_distance`` ahead, mapped
back by classic's near-identity map, which clips omega to +/- pi.

Differential drive (``create_unicycle_differential_drive_barrier_certificate``, ``..._with_boundary``): the robust
certificate of :mod:`~robotarium_exp.rps_classic.utilities.barrier_certificates2`, with classic's defaults.
Classic's version without walls cannot run (it calls a solver it never imports); this one does.

The QPs are solved as V2's are (:func:`~robotarium_exp.rps.utilities.barrier_certificates.use_qp_solver`): by
default as classic solves them, with cvxopt at the testbed's tolerances, so they answer as classic's do. Solver
failures do what V2's certificates do here: a warning, zero velocities, a count in ``stats``.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable

import numpy as np

from robotarium_exp.rps.utilities.barrier_certificates import (
    BarrierStats,
    Certificate,
    FloatArray,
    _check_pair,
    _solve_qp,
    _spec,
)
from robotarium_exp.rps.utilities.barrier_rows import barrier_rows
from robotarium_exp.rps_classic.utilities.barrier_certificates2 import RobustCertificate
from robotarium_exp.rps_classic.utilities.transformations import create_si_to_uni_mapping, create_uni_to_si_dynamics

__all__ = [
    'create_single_integrator_barrier_certificate',
    'create_single_integrator_barrier_certificate2',
    'create_single_integrator_barrier_certificate_with_boundary',
    'create_unicycle_barrier_certificate',
    'create_unicycle_barrier_certificate2',
    'create_unicycle_barrier_certificate_with_boundary',
    'create_unicycle_differential_drive_barrier_certificate',
    'create_unicycle_differential_drive_barrier_certificate_with_boundary',
]

CLASSIC_BOUNDARY = np.array([-1.6, 1.6, -1.0, 1.0])
"""Classic's default ``boundary_points``: [x_min, x_max, y_min, y_max]."""

SiCertificate = Callable[[FloatArray, FloatArray], FloatArray]


class UnsafeGainCertificate:
    """``certificate(dxi, x) -> dxi``: pairwise rows whose gain is ``unsafe_barrier_gain`` for pairs inside the
    safety radius, ``barrier_gain`` otherwise; with ``stats`` like V2's certificates."""

    def __init__(
        self, barrier_gain: float, unsafe_barrier_gain: float, safety_radius: float, magnitude_limit: float
    ) -> None:
        self.spec = _spec(safety_radius, barrier_gain, magnitude_limit, None, False)
        self.unsafe_barrier_gain = float(unsafe_barrier_gain)
        self.stats = BarrierStats()

    def __call__(self, dxi: FloatArray, x: FloatArray) -> FloatArray:
        dxi, x = _check_pair(dxi, x, 'dxi', 'x')
        n = dxi.shape[1]
        norms = np.hypot(dxi[0], dxi[1])
        over = norms > self.spec.magnitude_limit
        dxi[:, over] *= self.spec.magnitude_limit / norms[over]
        a, b = barrier_rows(x[:2], self.spec)  # without polygon or walls: exactly the pairs, gamma h^3 each
        b[b < 0] *= self.unsafe_barrier_gain / self.spec.barrier_gain
        self.stats.solves += 1
        self.stats.rows_last = a.shape[0]
        safe = _solve_qp(n, dxi, a, b)
        if safe is None:
            self.stats.failures += 1
            message = f'barrier QP infeasible at solve {self.stats.solves}; commanding zero velocities'
            self.stats.messages.append(message)
            warnings.warn(f'QP failed. Commanding zero velocities. ({message})', RuntimeWarning, stacklevel=2)
            return np.zeros_like(dxi)
        return safe


class ClassicUnicycleCertificate:
    """``certificate(dxu, poses) -> dxu``: a single-integrator certificate at the projection points, mapped back
    with classic's near-identity map (omega clipped to +/- pi); ``stats`` are the inner certificate's."""

    def __init__(self, inner: Certificate | UnsafeGainCertificate, projection_distance: float) -> None:
        self.inner = inner
        self.si_to_uni_dyn, self.uni_to_si_states = create_si_to_uni_mapping(projection_distance=projection_distance)
        self.uni_to_si_dyn = create_uni_to_si_dynamics(projection_distance=projection_distance)

    @property
    def stats(self) -> BarrierStats:
        return self.inner.stats

    def __call__(self, dxu: FloatArray, x: FloatArray) -> FloatArray:
        dxu, x = _check_pair(dxu, x, 'dxu', 'x', state_rows=3)
        safe = self.inner(self.uni_to_si_dyn(dxu, x), self.uni_to_si_states(x))
        return self.si_to_uni_dyn(safe, x)


def create_single_integrator_barrier_certificate(
    barrier_gain: float = 100, safety_radius: float = 0.17, magnitude_limit: float = 0.2
) -> Certificate:
    """Pairwise barriers, no speed polygon (the input is first scaled to the limit)."""
    return Certificate(_spec(safety_radius, barrier_gain, magnitude_limit, None, False))


def create_single_integrator_barrier_certificate_with_boundary(
    barrier_gain: float = 100,
    safety_radius: float = 0.17,
    magnitude_limit: float = 0.2,
    boundary_points: FloatArray = CLASSIC_BOUNDARY,
) -> Certificate:
    """Pairwise and boundary barriers (a lone robot still meets the walls)."""
    return Certificate(_spec(safety_radius, barrier_gain, magnitude_limit, boundary_points, False))


def create_single_integrator_barrier_certificate2(
    barrier_gain: float = 100,
    unsafe_barrier_gain: float = 1e6,
    safety_radius: float = 0.17,
    magnitude_limit: float = 0.2,
) -> UnsafeGainCertificate:
    """Classic: pairwise barriers, ``unsafe_barrier_gain`` on pairs already inside the safety radius."""
    return UnsafeGainCertificate(barrier_gain, unsafe_barrier_gain, safety_radius, magnitude_limit)


def create_unicycle_barrier_certificate(
    barrier_gain: float = 100,
    safety_radius: float = 0.12,
    projection_distance: float = 0.05,
    magnitude_limit: float = 0.2,
) -> ClassicUnicycleCertificate:
    """Classic: the SI certificate (radius safety_radius + d) at the projection points."""
    inner = create_single_integrator_barrier_certificate(
        barrier_gain=barrier_gain, safety_radius=safety_radius + projection_distance
    )
    return ClassicUnicycleCertificate(inner, projection_distance)


def create_unicycle_barrier_certificate_with_boundary(
    barrier_gain: float = 100,
    safety_radius: float = 0.12,
    projection_distance: float = 0.05,
    magnitude_limit: float = 0.2,
    boundary_points: FloatArray = CLASSIC_BOUNDARY,
) -> ClassicUnicycleCertificate:
    """Classic: as above, with the walls of ``boundary_points``."""
    inner = create_single_integrator_barrier_certificate_with_boundary(
        barrier_gain=barrier_gain, safety_radius=safety_radius + projection_distance, boundary_points=boundary_points
    )
    return ClassicUnicycleCertificate(inner, projection_distance)


def create_unicycle_barrier_certificate2(
    barrier_gain: float = 500,
    unsafe_barrier_gain: float = 1e6,
    safety_radius: float = 0.12,
    projection_distance: float = 0.05,
    magnitude_limit: float = 0.2,
) -> ClassicUnicycleCertificate:
    """Classic: :func:`create_single_integrator_barrier_certificate2` at the projection points."""
    inner = create_single_integrator_barrier_certificate2(
        barrier_gain=barrier_gain,
        unsafe_barrier_gain=unsafe_barrier_gain,
        safety_radius=safety_radius + projection_distance,
    )
    return ClassicUnicycleCertificate(inner, projection_distance)


def create_unicycle_differential_drive_barrier_certificate(
    max_num_obstacle_points: int = 100,
    max_num_robots: int = 30,
    disturbance: float = 5,
    wheel_vel_limit: float = 12.5,
    base_length: float = 0.105,
    wheel_radius: float = 0.016,
    projection_distance: float = 0.05,
    barrier_gain: float = 150,
    safety_radius: float = 0.17,
) -> RobustCertificate:
    """Classic: the robust certificate on wheel speeds (``f(dxu, x, obstacles=np.empty(0))``), without walls."""
    return RobustCertificate(
        disturbance, wheel_vel_limit, base_length, wheel_radius, projection_distance, barrier_gain, safety_radius, None
    )


def create_unicycle_differential_drive_barrier_certificate_with_boundary(
    max_num_obstacle_points: int = 100,
    max_num_robots: int = 30,
    disturbance: float = 5,
    wheel_vel_limit: float = 12.5,
    base_length: float = 0.105,
    wheel_radius: float = 0.016,
    projection_distance: float = 0.05,
    barrier_gain: float = 150,
    safety_radius: float = 0.17,
    boundary_points: FloatArray = CLASSIC_BOUNDARY,
) -> RobustCertificate:
    """Classic: the robust certificate with the walls of ``boundary_points`` (kept by the projection points)."""
    return RobustCertificate(
        disturbance,
        wheel_vel_limit,
        base_length,
        wheel_radius,
        projection_distance,
        barrier_gain,
        safety_radius,
        np.asarray(boundary_points, dtype=float),
    )
