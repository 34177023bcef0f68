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
certificate of `barrier_certificates2`, with classic's defaults.
Classic's version without walls cannot run (it calls a solver it never imports); this one does.

The QPs are solved as V2's are (`use_qp_solver`): by
default as classic solves them, with cvxopt at the testbed's tolerances, so they answer as classic's do. Solver
failures do what V2's certificates do here: a warning, zero velocities, a count in ``stats``.
"""

from __future__ import annotations

import operator
import warnings
from collections.abc import Callable

import numpy as np

from robotarium_exp.rps.errors import RobotariumError
from robotarium_exp.rps.utilities.barrier_certificates import BarrierStats, Certificate, FloatArray, _solve_qp
from robotarium_exp.rps.utilities.barrier_inputs import checked_pair
from robotarium_exp.rps.utilities.barrier_rows import BarrierSpec, barrier_rows
from robotarium_exp.rps_classic.utilities.barrier_certificates2 import RobustCertificate
from robotarium_exp.rps_classic.utilities.checks import (
    ARRAY,
    POSITIVE,
    Check,
    Checked,
    Rule,
    bound,
    columns,
    enforce,
    pair,
    rows,
    typed,
)
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

WORDS = {
    'barrier_gain': 'the barrier gain (barrier_gain)',
    'safety_radius': 'the safe distance between robots (safety_radius)',
    'projection_distance': 'the projected point distance for the diffeomorphism between sinlge integrator and unicycle '
    '(projection_distance)',
    'magnitude_limit': 'the maximum linear velocity of the robot (magnitude_limit)',
}
"""How classic's certificate factories name their arguments (the ``2`` variants name the gains as below)."""

GAINS_2 = {'barrier_gain': 'the barrier gain inside the safe set (barrier_gain)'}
DIAMETER = 'be greater than or equal to the diameter of the robot (0.12m)'
SI_DIAMETER = f'{DIAMETER} plus the distance to the look ahead point used in the diffeomorphism if that is being used'


def _factory_checks(names: tuple[str, ...], words: dict[str, str], diameter: str) -> tuple[Check, ...]:
    """A certificate factory's checks, as classic orders them: every argument's type, then every range."""
    words = {**WORDS, **words}
    ranges: dict[str, list[Rule]] = {
        'barrier_gain': [POSITIVE],
        'unsafe_barrier_gain': [POSITIVE],
        'safety_radius': [(operator.ge, 0.12, diameter)],
        'projection_distance': [POSITIVE],
        'magnitude_limit': [POSITIVE, (operator.le, 0.2, 'be less than the max speed of the robot (0.2m/s)')],
    }
    return tuple(typed(name, words[name]) for name in names) + tuple(
        bound(name, words[name], rule) for name in names for rule in ranges[name]
    )


SI_ARGUMENTS = ('barrier_gain', 'safety_radius', 'magnitude_limit')
UNI_ARGUMENTS = ('barrier_gain', 'safety_radius', 'projection_distance', 'magnitude_limit')
SI_FACTORY = _factory_checks(SI_ARGUMENTS, {}, SI_DIAMETER)
SI_FACTORY_2 = _factory_checks(
    ('barrier_gain', 'unsafe_barrier_gain', 'safety_radius', 'magnitude_limit'),
    {**GAINS_2, 'unsafe_barrier_gain': 'the barrier gain if outside the safe set (unsafe_barrier_gain)'},
    SI_DIAMETER,
)
UNI_FACTORY = _factory_checks(UNI_ARGUMENTS, {}, DIAMETER)
UNI_FACTORY_2 = _factory_checks(
    ('barrier_gain', 'unsafe_barrier_gain', 'safety_radius', 'projection_distance', 'magnitude_limit'),
    {**GAINS_2, 'unsafe_barrier_gain': 'the barrier gain outside the safe set (unsafe_barrier_gain)'},
    DIAMETER,
)


def _certificate_checks(
    command: str, typed_as: str, named: str, layout: str, x_rows: int, x_layout: str
) -> tuple[Check, ...]:
    """The checks of a created certificate ``f(command, x)``, in classic's order; ``typed_as`` and ``named`` are
    classic's two spellings of the command's kind, ``layout`` and ``x_layout`` its rows and the states'."""
    x_kind = named if command == 'dxi' else typed_as
    return (
        typed(command, f'the {typed_as} robot velocity command ({command})', ARRAY),
        typed('x', 'the robot states (x)', ARRAY),
        rows('x', x_rows, f'the dimension of the {x_kind} robot states (x) must be {x_rows} ({x_layout})'),
        rows(command, 2, f'the dimension of the robot {named} velocity command ({command}) must be 2 ({layout})'),
        columns(
            'x',
            command,
            f'the number of robot states (x) must be equal to the number of robot {named} velocity commands '
            f'({command}). Recieved a current robot pose input array (x) of size %r x %r and single integrator '
            'velocity array (dxi) of size %r x %r.',
        ),
    )


SI_CERTIFICATE = _certificate_checks('dxi', 'single-integrator', 'single integrator', '[x_dot;y_dot]', 2, '[x;y]')
UNI_CERTIFICATE = _certificate_checks('dxu', 'unicycle', 'unicycle', '[v;w]', 3, '[x;y;theta]')


def _spec(
    safety_radius: float,
    barrier_gain: float,
    magnitude_limit: float,
    boundary: object,
    polygon: bool,
    *,
    full_first_side: bool = True,
) -> BarrierSpec:
    for name, value in (
        ('safety_radius', safety_radius),
        ('barrier_gain', barrier_gain),
        ('magnitude_limit', magnitude_limit),
    ):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
            msg = f'{name} must be a positive number; got {value!r}.'
            raise RobotariumError(msg)
    bounds = None if boundary is None else tuple(float(v) for v in np.asarray(boundary, dtype=float).ravel())
    if bounds is not None and len(bounds) != 4:
        msg = f'boundary_points must be [x_min, x_max, y_min, y_max]; got {boundary!r}.'
        raise RobotariumError(msg)
    return BarrierSpec(
        float(safety_radius), float(barrier_gain), float(magnitude_limit), bounds, polygon, full_first_side
    )


def _checked(certificate: Callable[..., FloatArray], created_by: str) -> Checked:
    """``certificate`` behind the checks classic makes of the certificates that ``created_by`` creates."""
    checks, command = (UNI_CERTIFICATE, 'dxu') if 'unicycle' in created_by else (SI_CERTIFICATE, 'dxi')
    return Checked(certificate, pair(f'In the function created by the {created_by} function', checks, command, 'x'))


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
        dxi, x = checked_pair(dxi, x, 'dxi', 'x')
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

    def __init__(self, inner: Checked, projection_distance: float) -> None:
        self.inner = inner
        self.si_to_uni_dyn, self.uni_to_si_states = create_si_to_uni_mapping(projection_distance=projection_distance)
        self.uni_to_si_dyn = create_uni_to_si_dynamics(projection_distance=projection_distance)

    @property
    def stats(self) -> BarrierStats:
        stats: BarrierStats = self.inner.stats
        return stats

    def __call__(self, dxu: FloatArray, x: FloatArray) -> FloatArray:
        dxu, x = checked_pair(dxu, x, 'dxu', 'x', state_rows=3)
        safe = self.inner(self.uni_to_si_dyn(dxu, x), self.uni_to_si_states(x))
        return self.si_to_uni_dyn(safe, x)


def create_single_integrator_barrier_certificate(
    barrier_gain: float = 100, safety_radius: float = 0.17, magnitude_limit: float = 0.2
) -> Checked:
    """Pairwise barriers, no speed polygon (the input is first scaled to the limit)."""
    enforce('In the function create_single_integrator_barrier_certificate', SI_FACTORY, locals())
    return _checked(
        Certificate(_spec(safety_radius, barrier_gain, magnitude_limit, None, False)),
        'create_single_integrator_barrier_certificate',
    )


def create_single_integrator_barrier_certificate_with_boundary(
    barrier_gain: float = 100,
    safety_radius: float = 0.17,
    magnitude_limit: float = 0.2,
    boundary_points: FloatArray = CLASSIC_BOUNDARY,
) -> Checked:
    """Pairwise and boundary barriers (a lone robot still meets the walls)."""
    enforce('In the function create_single_integrator_barrier_certificate', SI_FACTORY, locals())
    certificate = Certificate(_spec(safety_radius, barrier_gain, magnitude_limit, boundary_points, False))
    return _checked(certificate, 'create_single_integrator_barrier_certificate')


def create_single_integrator_barrier_certificate2(
    barrier_gain: float = 100,
    unsafe_barrier_gain: float = 1e6,
    safety_radius: float = 0.17,
    magnitude_limit: float = 0.2,
) -> Checked:
    """Classic: pairwise barriers, ``unsafe_barrier_gain`` on pairs already inside the safety radius."""
    enforce('In the function create_single_integrator_barrier_certificate2', SI_FACTORY_2, locals())
    certificate = UnsafeGainCertificate(barrier_gain, unsafe_barrier_gain, safety_radius, magnitude_limit)
    return _checked(certificate, 'create_single_integrator_barrier_certificate2')


def create_unicycle_barrier_certificate(
    barrier_gain: float = 100,
    safety_radius: float = 0.12,
    projection_distance: float = 0.05,
    magnitude_limit: float = 0.2,
) -> Checked:
    """Classic: the SI certificate (radius safety_radius + d) at the projection points."""
    enforce('In the function create_unicycle_barrier_certificate', UNI_FACTORY, locals())
    inner = create_single_integrator_barrier_certificate(
        barrier_gain=barrier_gain, safety_radius=safety_radius + projection_distance
    )
    return _checked(ClassicUnicycleCertificate(inner, projection_distance), 'create_unicycle_barrier_certificate')


def create_unicycle_barrier_certificate_with_boundary(
    barrier_gain: float = 100,
    safety_radius: float = 0.12,
    projection_distance: float = 0.05,
    magnitude_limit: float = 0.2,
    boundary_points: FloatArray = CLASSIC_BOUNDARY,
) -> Checked:
    """Classic: as above, with the walls of ``boundary_points``."""
    enforce('In the function create_unicycle_barrier_certificate', UNI_FACTORY, locals())
    inner = create_single_integrator_barrier_certificate_with_boundary(
        barrier_gain=barrier_gain, safety_radius=safety_radius + projection_distance, boundary_points=boundary_points
    )
    return _checked(ClassicUnicycleCertificate(inner, projection_distance), 'create_unicycle_barrier_certificate')


def create_unicycle_barrier_certificate2(
    barrier_gain: float = 500,
    unsafe_barrier_gain: float = 1e6,
    safety_radius: float = 0.12,
    projection_distance: float = 0.05,
    magnitude_limit: float = 0.2,
) -> Checked:
    """Classic: `create_single_integrator_barrier_certificate2` at the projection points."""
    enforce('In the function create_unicycle_barrier_certificate2', UNI_FACTORY_2, locals())
    inner = create_single_integrator_barrier_certificate2(
        barrier_gain=barrier_gain,
        unsafe_barrier_gain=unsafe_barrier_gain,
        safety_radius=safety_radius + projection_distance,
    )
    return _checked(ClassicUnicycleCertificate(inner, projection_distance), 'create_unicycle_barrier_certificate')


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
        disturbance,
        wheel_vel_limit,
        base_length,
        wheel_radius,
        projection_distance,
        barrier_gain,
        safety_radius,
        None,
        sizes=(max_num_obstacle_points, max_num_robots, 0),
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
        sizes=(max_num_obstacle_points, max_num_robots, 0),
    )
