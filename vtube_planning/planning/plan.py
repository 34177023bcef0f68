"""The result of speed and density planning, and its certificate.

A :class:`Plan` holds the planned average forward speed v*(l) and density rho*(l) on an arc-length grid and
says how it is to be used between grid points: the slowness w = 1/v and the density are interpolated linearly
(so the traversal time, the integral of w, and the density term of (p1) are exact for the interpolated plan).
Its certificate is the largest relative violation of each original constraint (p2)-(p7), evaluated on a grid
ten times finer than the solve grid, on the plan interpolated exactly that way.

Plans are saved as ``.npz`` files of plain arrays plus one JSON string (loaded without pickle).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from vtube_planning.errors import PlanError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.npzfile import read_npz, write_npz
from vtube_planning.onboard import PlanProfile
from vtube_planning.params import PlanningOptions, SwarmParams
from vtube_planning.planning.density import predicted_density

FloatArray = NDArray[np.float64]

RHO_EPSILON = 1e-3
"""Lower bound of the density in (p5), robots/m^2: the paper's strict ``rho > 0`` (resolution A14)."""
FINE_FACTOR = 10
"""The certificate's grid is this many times finer than the solve grid."""
ACTIVE_RTOL = 1e-3
"""A constraint is reported active at a grid point when its relative slack is below this."""
CONSTRAINTS = ('p2', 'p3', 'p4', 'p5', 'p6', 'p7', 'initial')
ARRAYS = ('l_m', 'speed_mps', 'density_per_m2', 'half_width_m', 'speed_limit_mps')
FORMAT_VERSION = 2


@dataclass(frozen=True)
class Plan:
    """Planned average forward speed and density along a tube.

    Attributes
    ----------
    l_m
        Arc-length grid, (K+1,), from 0 to L.
    speed_mps
        v*(l) at the grid points, (K+1,).
    density_per_m2
        rho*(l) at the grid points, (K+1,).
    half_width_m
        The tube's lambda(l) at the grid points (kept for plots and reports), (K+1,).
    speed_limit_mps
        The curvature limit sqrt(a_n r_t) of (p4) at the grid points (inf on straight parts), (K+1,).
    time_s
        Traversal time of the interpolated plan, integral of dl / v*.
    objective
        Terms of (p1): ``time_s``, ``density`` (integral of (rho - rho_d)^2 times mu), ``total``.
    certificate
        Largest relative violation of each constraint on the fine grid (``CONSTRAINTS``), >= 0.
    active
        Per constraint, where it binds at the grid points, (K+1,) bool arrays.
    method, status, iterations, solve_time_s
        How the plan was found.
    scene, swarm, options, tube_hash
        What it was planned for: the scene's name, the swarm, the planning options and the tube's
        :meth:`~vtube_planning.geometry.tube.VirtualTube.fingerprint`. :meth:`check_matches` refuses other ones.
    """

    l_m: FloatArray
    speed_mps: FloatArray
    density_per_m2: FloatArray
    half_width_m: FloatArray
    speed_limit_mps: FloatArray
    time_s: float
    objective: dict[str, float]
    certificate: dict[str, float]
    active: dict[str, NDArray[np.bool_]]
    method: str
    status: str
    iterations: int
    solve_time_s: float
    scene: str
    swarm: SwarmParams
    options: PlanningOptions
    tube_hash: str
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def length_m(self) -> float:
        return float(self.l_m[-1])

    @property
    def max_violation(self) -> float:
        """The certificate's worst entry."""
        return max(self.certificate.values())

    def is_certified(self, rtol: float = 1e-6) -> bool:
        """True when every constraint holds on the fine grid to the relative tolerance."""
        return self.max_violation <= rtol

    @property
    def profile(self) -> PlanProfile:
        """The plan as the controller uses it (slowness and density, linear between grid points)."""
        return PlanProfile(self.l_m, 1.0 / self.speed_mps, self.density_per_m2)

    def speed(self, l_m: ArrayLike) -> FloatArray:
        """v*(l) as used: 1 / (linear interpolation of the slowness); end values outside [0, L]."""
        return self.profile.speed(l_m)

    def density(self, l_m: ArrayLike) -> FloatArray:
        """rho*(l) as used: linear interpolation; end values outside [0, L]."""
        return self.profile.density(l_m)

    def check_matches(
        self, tube: VirtualTube, swarm: SwarmParams, options: PlanningOptions | None = None, *, scene: str | None = None
    ) -> None:
        """Raise :class:`PlanError` unless this plan was made for this tube, swarm (and options, when given).

        The scene's name alone does not decide (a copied scene file plans the same); it is named in the message.
        """
        made_for = f'the plan (made for scene {self.scene!r})'
        here = f'scene {scene!r}' if scene is not None else 'this run'
        problems = []
        if self.tube_hash != tube.fingerprint():
            problems.append('a different tube')
        if self.swarm != swarm:
            changed = [k for k, v in asdict(swarm).items() if asdict(self.swarm)[k] != v]
            problems.append(f'other swarm parameters ({", ".join(changed)})')
        if options is not None and self.options != options:
            changed = [k for k, v in asdict(options).items() if asdict(self.options)[k] != v]
            problems.append(f'other planning options ({", ".join(changed)})')
        if problems:
            msg = (
                f'{made_for} does not fit {here}: it was made for {" and ".join(problems)}. Plan this scene '
                'first (vtube plan SCENE --out DIR) and pass that plan.'
            )
            raise PlanError(msg)

    def save(self, path: str | Path) -> Path:
        """Write the plan to an ``.npz`` file (arrays and one JSON string; no pickle)."""
        meta = {
            'format_version': FORMAT_VERSION,
            'time_s': self.time_s,
            'objective': self.objective,
            'certificate': self.certificate,
            'method': self.method,
            'status': self.status,
            'iterations': self.iterations,
            'solve_time_s': self.solve_time_s,
            'scene': self.scene,
            'swarm': asdict(self.swarm),
            'options': asdict(self.options),
            'tube_hash': self.tube_hash,
            'extra': self.extra,
        }
        arrays = {name: getattr(self, name) for name in ARRAYS}
        arrays.update({f'active_{k}': v for k, v in self.active.items()})
        return write_npz(path, arrays, meta)

    @classmethod
    def load(cls, path: str | Path) -> Plan:
        """Read a plan written by :meth:`save`."""
        arrays, meta = read_npz(path, PlanError, 'plan file')
        if meta.get('format_version') != FORMAT_VERSION:
            msg = (
                f'plan file {str(path)!r} has format {meta.get("format_version")!r}; this vtube reads format '
                f'{FORMAT_VERSION} (format 1 plans do not record their tube). Plan again with vtube plan.'
            )
            raise PlanError(msg)
        active = {k.removeprefix('active_'): arrays.pop(k) for k in list(arrays) if k.startswith('active_')}
        fields = [
            *('time_s', 'objective', 'certificate', 'method', 'status', 'iterations', 'solve_time_s', 'scene'),
            *('swarm', 'options', 'tube_hash', 'extra'),
        ]
        missing = [name for name in ARRAYS if name not in arrays] + [name for name in fields if name not in meta]
        extra = [name for name in arrays if name not in ARRAYS]
        shapes = {name: arrays[name].shape for name in ARRAYS if name in arrays}
        if missing or extra or len(set(shapes.values())) > 1 or any(len(shape) != 1 for shape in shapes.values()):
            msg = (
                f'plan file {str(path)!r} is damaged: expected the arrays {list(ARRAYS)} of one length and the '
                f'fields {fields}; missing {missing}, unexpected {extra}, shapes {shapes}. Plan again with '
                'vtube plan.'
            )
            raise PlanError(msg)
        try:
            swarm, options = SwarmParams(**meta['swarm']), PlanningOptions(**meta['options'])
        except (TypeError, ValueError) as err:
            msg = f'plan file {str(path)!r} records parameters this vtube does not know ({err}). Plan again with vtube plan.'
            raise PlanError(msg) from err
        return cls(
            **arrays,
            time_s=meta['time_s'],
            objective=meta['objective'],
            certificate=meta['certificate'],
            active=active,
            method=meta['method'],
            status=meta['status'],
            iterations=meta['iterations'],
            solve_time_s=meta['solve_time_s'],
            scene=meta['scene'],
            swarm=swarm,
            options=options,
            tube_hash=meta['tube_hash'],
            extra=meta['extra'],
        )


def initial_conditions(swarm: SwarmParams, options: PlanningOptions) -> tuple[float, float]:
    """Boundary values (v_a(0), rho_a(0)): the options', or v_min and the packing density (resolution A15)."""
    v0 = swarm.v_min_mps if options.v0_mps is None else float(options.v0_mps)
    rho0 = swarm.rho_packing if options.rho0_per_m2 is None else float(options.rho0_per_m2)
    return v0, rho0


def curvature_speed_limit(tube: VirtualTube, swarm: SwarmParams, l_m: FloatArray) -> FloatArray:
    """sqrt(a_n r_t(l)) of (p4), inf where the tube is straight."""
    return np.sqrt(swarm.a_n_mps2 * np.asarray(tube.curvature_radius(l_m)))


def objective_terms(
    l_m: FloatArray, speed_mps: FloatArray, density: FloatArray, swarm: SwarmParams, options: PlanningOptions
) -> dict[str, float]:
    """(p1) for the plan interpolated as used: exact integrals of w and of mu (rho - rho_d)^2 (piecewise linear)."""
    dl = np.diff(l_m)
    w = 1.0 / speed_mps
    e = density - swarm.rho_d_per_m2
    time_s = float(np.sum(0.5 * dl * (w[:-1] + w[1:])))
    dens = float(options.density_weight * np.sum(dl / 3.0 * (e[:-1] ** 2 + e[:-1] * e[1:] + e[1:] ** 2)))
    return {'time_s': time_s, 'density': dens, 'total': time_s + dens}


def certify(
    tube: VirtualTube,
    swarm: SwarmParams,
    options: PlanningOptions,
    l_m: FloatArray,
    speed_mps: FloatArray,
    density: FloatArray,
) -> tuple[dict[str, float], dict[str, NDArray[np.bool_]]]:
    """Relative violations of (p2)-(p7) and of the initial values on a 10x finer grid, and the active sets.

    Violations are divided by the constraint's own bound (v_min or v_max, a_v, sqrt(a_n r_t), rho_max, a_rho,
    the initial value). Between fine points the plan is piecewise linear in w and rho, so rates are exact per
    fine interval and (p3), (p6) use the interval's largest speed.
    """
    fine = np.interp(np.linspace(0.0, l_m.size - 1, FINE_FACTOR * (l_m.size - 1) + 1), np.arange(l_m.size), l_m)
    w_nodes = 1.0 / speed_mps
    w = np.interp(fine, l_m, w_nodes)
    v = 1.0 / w
    rho = np.interp(fine, l_m, density)
    dl = np.diff(fine)
    v_top = np.maximum(v[:-1], v[1:])
    a_rho = swarm.a_rho
    limit = curvature_speed_limit(tube, swarm, fine)
    v0, rho0 = initial_conditions(swarm, options)
    rho_f = predicted_density(tube, fine, rho, swarm.n_robots, options.lookahead_m, options.predictive_model)
    curved = np.isfinite(limit)

    def worst(values: FloatArray) -> float:
        return float(max(0.0, np.max(values))) if values.size else 0.0

    certificate = {
        'p2': max(worst((swarm.v_min_mps - v) / swarm.v_min_mps), worst((v - swarm.v_max_mps) / swarm.v_max_mps)),
        'p3': worst((np.abs(np.diff(w)) / dl / np.minimum(w[:-1], w[1:]) ** 3 - swarm.a_v_mps2) / swarm.a_v_mps2),
        'p4': worst((v[curved] - limit[curved]) / limit[curved]),
        'p5': max(
            worst((rho - swarm.rho_max_per_m2) / swarm.rho_max_per_m2),
            worst((RHO_EPSILON - rho) / swarm.rho_max_per_m2),
        ),
        'p6': worst((np.abs(np.diff(rho)) / dl * v_top - a_rho) / a_rho),
        'p7': worst((np.abs(rho_f - rho) / options.lookahead_m * v - a_rho) / a_rho),
        'initial': max(abs(speed_mps[0] - v0) / v0, abs(density[0] - rho0) / rho0),
    }
    # active sets at the grid points
    node_limit = curvature_speed_limit(tube, swarm, l_m)
    d_w = np.abs(np.diff(w_nodes)) / np.diff(l_m) / np.minimum(w_nodes[:-1], w_nodes[1:]) ** 3
    d_rho = np.abs(np.diff(density)) / np.diff(l_m) * np.maximum(speed_mps[:-1], speed_mps[1:])
    # (p7) as the planner imposes it: the interval's largest relative change times its largest rho and v
    change = np.abs(rho_f / rho - 1.0)
    blocks = change[:-1].reshape(l_m.size - 1, FINE_FACTOR).max(axis=1)
    change_max = np.maximum(blocks, change[FINE_FACTOR::FINE_FACTOR])
    p7_rate = change_max * np.maximum(density[:-1], density[1:]) * np.maximum(speed_mps[:-1], speed_mps[1:])

    def on_nodes(per_interval: NDArray[np.bool_]) -> NDArray[np.bool_]:
        return np.concatenate([per_interval, [False]]) | np.concatenate([[False], per_interval])

    tol = ACTIVE_RTOL
    active = {
        'v_max': speed_mps >= swarm.v_max_mps * (1 - tol),
        'v_min': speed_mps <= swarm.v_min_mps * (1 + tol),
        'p3': on_nodes(d_w >= swarm.a_v_mps2 * (1 - tol)),
        'p4': speed_mps >= node_limit * (1 - tol),
        'p6': on_nodes(d_rho >= a_rho * (1 - tol)),
        'p7': on_nodes(p7_rate / options.lookahead_m >= a_rho * (1 - tol)),
    }
    return certificate, active
