"""The result of speed and density planning: the [`Plan`][vtube_planning.planning.plan.Plan], how it was solved, and
its ``.npz`` form.

A [`Plan`][vtube_planning.planning.plan.Plan] holds the planned average forward speed v*(l) and density rho*(l) on an
arc-length grid and says how it is to be used between grid points: the slowness w = 1/v and the density are
interpolated linearly (so the traversal time, the integral of w, and the density term of (p1) are exact for the
interpolated plan). Its certificate is the largest relative violation of each original constraint (p2)-(p7), evaluated
on a grid ten times finer than the solve grid, on the plan interpolated exactly that way
(`certify`).

Plans are saved as ``.npz`` files of plain arrays plus one JSON string (loaded without pickle).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from vtube_planning.errors import PlanError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.npzfile import read_npz, write_npz
from vtube_planning.onboard import PlanProfile
from vtube_planning.params import PlanningOptions, SwarmParams
from vtube_planning.planning.constraints import (
    MEANINGS,
    certify,
    curvature_speed_limit,
    objective_terms,
    planned_limits,
    worst_places,
)

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

Method = Literal['convex', 'polynomial', 'flat']
"""How a plan was made: the convex-concave procedure, the paper's cubic segments, or the study's constant profile
on another plan's grid."""
Status = Literal['converged', 'iteration limit']
Formulation = Literal['banded', 'cvxpy']
"""How each convex subproblem is solved: the banded interior-point solver, or the cvxpy reference."""
Start = Literal['fastest', 'slowest']
"""The admissible profile the convex-concave procedure starts from."""

ARRAYS = ('l_m', 'speed_mps', 'density_per_m2', 'half_width_m', 'speed_limit_mps')
FORMAT_VERSION = 3


@dataclass(frozen=True)
class SwarmState:
    """What replanning starts from: the swarm's arc length, average forward speed and density, measured now.

    Parameters
    ----------
    arc_length_m
        Where the swarm is along the tube (the mean arc length of its working robots), in [0, L).
    speed_mps
        Its average forward speed, m/s.
    density_per_m2
        Its measured density, robots/m^2.
    n_robots
        The robots still flying, when fewer than the plan was made for (a robot failed); None: the plan's swarm.
    """

    arc_length_m: float
    speed_mps: float
    density_per_m2: float
    n_robots: int | None = None


@dataclass(frozen=True)
class ReplanStart:
    """The state a replanned plan starts from: as measured, and the speed and density it was planned from (the
    measured ones clipped into the constraints)."""

    measured: SwarmState
    speed_mps: float
    density_per_m2: float


@dataclass(frozen=True)
class PolynomialFit:
    """The polynomial method's solution: its segments, (p1) of the polynomials themselves (s), and the l1 slack
    of (p3) left at the end."""

    segments: int
    objective: float
    p3_slack: float


@dataclass(frozen=True)
class SolveRecord:
    """How a plan was found: method, status, convex-concave iterations and wall time; for the convex method the
    formulation that solved and the start; for a replanned plan the state it started from; for the polynomial
    method its fit."""

    method: Method
    status: Status
    iterations: int
    solve_time_s: float
    formulation: Formulation | None = None
    start: Start | None = None
    replanned_from: ReplanStart | None = None
    polynomial: PolynomialFit | None = None

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> SolveRecord:
        """The record from its JSON form (``dataclasses.asdict``); TypeError or KeyError if it is not one."""
        fields = dict(data)
        replanned, fit = fields.pop('replanned_from'), fields.pop('polynomial')
        if replanned is not None:
            measured = SwarmState(**replanned['measured'])
            replanned = ReplanStart(measured, replanned['speed_mps'], replanned['density_per_m2'])
        return cls(**fields, replanned_from=replanned, polynomial=None if fit is None else PolynomialFit(**fit))


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
        Terms of (p1): ``time_s``, ``density`` (integral of (rho - rho_d)^2 times mu), ``total``; planned for the
        last robot out (``options.objective``) also ``entry_s`` and ``exit_s``, the half-extent terms.
    certificate
        Largest relative violation of each constraint on the fine grid
        (`CONSTRAINTS`), >= 0.
    active
        Per constraint, where it binds at the grid points, (K+1,) bool arrays.
    solved
        How the plan was found (`SolveRecord`).
    scene, swarm, options, tube_hash
        What it was planned for: the scene's name, the swarm, the planning options and the tube's
        [`fingerprint`][vtube_planning.geometry.tube.VirtualTube.fingerprint].
        [`check_matches`][vtube_planning.planning.plan.Plan.check_matches] refuses other ones.
    provenance
        Where it was made (`provenance`), when recorded.

    The arrays are read-only copies.
    """

    l_m: FloatArray
    speed_mps: FloatArray
    density_per_m2: FloatArray
    half_width_m: FloatArray
    speed_limit_mps: FloatArray
    time_s: float
    objective: Mapping[str, float]
    certificate: Mapping[str, float]
    active: Mapping[str, BoolArray]
    solved: SolveRecord
    scene: str
    swarm: SwarmParams
    options: PlanningOptions
    tube_hash: str
    provenance: Mapping[str, object] | None = None

    def __post_init__(self) -> None:
        for name in ARRAYS:
            object.__setattr__(self, name, _read_only(getattr(self, name)))
        object.__setattr__(self, 'active', {name: _read_only(mask) for name, mask in self.active.items()})

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

    def failures(self, tube: VirtualTube, rtol: float = 1e-6) -> tuple[str, ...]:
        """Why the plan is not certified on ``tube`` (the one it was made for): each certificate entry above the
        relative tolerance, what it bounds, by how much and where it is worst; empty when certified."""
        broken = {name: value for name, value in self.certificate.items() if value > rtol}
        if not broken:
            return ()
        where = worst_places(tube, self.swarm, self.options, self.l_m, self.speed_mps, self.density_per_m2)
        return tuple(
            f'({name}) {MEANINGS[name]} is exceeded by {value:.1e} (relative) at l = {where[name]:.3f} m'
            if name != 'initial'
            else f'{MEANINGS[name]} miss the boundary values by {value:.1e} (relative)'
            for name, value in broken.items()
        )

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
        """Raise [`PlanError`][vtube_planning.errors.PlanError] unless this plan was made for this tube, swarm (and
        options, when given).

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
            'objective': dict(self.objective),
            'certificate': dict(self.certificate),
            'solved': asdict(self.solved),
            'scene': self.scene,
            'swarm': asdict(self.swarm),
            'options': asdict(self.options),
            'tube_hash': self.tube_hash,
            'provenance': None if self.provenance is None else dict(self.provenance),
        }
        arrays: dict[str, NDArray[Any]] = {name: getattr(self, name) for name in ARRAYS}
        arrays.update({f'active_{k}': v for k, v in self.active.items()})
        return write_npz(path, arrays, meta)

    @classmethod
    def load(cls, path: str | Path, tube: VirtualTube) -> Plan:
        """Read a plan written by [`save`][vtube_planning.planning.plan.Plan.save] for ``tube``. Its numbers are
        checked (finite; a grid from 0 to the tube's length; speeds and densities > 0), and everything derived from
        them (the certificate, the active sets, the objective, the tube's half-widths and speed limits) is computed
        again, never read from the file: an edited plan is judged by what it now holds."""
        where = f'plan file {str(path)!r}'
        arrays, meta = read_npz(path, PlanError, 'plan file')
        if meta.get('format_version') != FORMAT_VERSION:
            msg = (
                f'{where} has format {meta.get("format_version")!r}; this vtube reads format '
                f'{FORMAT_VERSION}. Plan again with vtube plan.'
            )
            raise PlanError(msg)
        active = [k for k in arrays if k.startswith('active_')]
        fields = ['time_s', 'objective', 'certificate', 'solved', 'scene', 'swarm', 'options', 'tube_hash']
        fields.append('provenance')
        missing = [name for name in ARRAYS if name not in arrays] + [name for name in fields if name not in meta]
        extra = [name for name in arrays if name not in ARRAYS and name not in active]
        shapes = {name: arrays[name].shape for name in ARRAYS if name in arrays}
        if missing or extra or len(set(shapes.values())) > 1 or any(len(shape) != 1 for shape in shapes.values()):
            msg = (
                f'{where} is damaged: expected the arrays {list(ARRAYS)} of one length and the '
                f'fields {fields}; missing {missing}, unexpected {extra}, shapes {shapes}. Plan again with '
                'vtube plan.'
            )
            raise PlanError(msg)
        if meta['tube_hash'] != tube.fingerprint():
            msg = (
                f'the plan in {where} (made for scene {meta["scene"]!r}) does not fit this tube: it was made for a '
                'different tube. Plan this scene first (vtube plan SCENE --out DIR) and pass that plan.'
            )
            raise PlanError(msg)
        try:
            if not isinstance(meta['provenance'], (dict, type(None))) or not isinstance(meta['scene'], str):
                raise TypeError('its scene must be a name and its provenance a table')
            swarm, options = SwarmParams(**meta['swarm']), PlanningOptions(**meta['options'])
            solved = SolveRecord.from_json(meta['solved'])
        except (TypeError, ValueError, KeyError) as err:
            msg = f'{where} records parameters this vtube does not know ({err}). Plan again with vtube plan.'
            raise PlanError(msg) from err
        l_m, speed, density = (np.asarray(arrays[k], dtype=float) for k in ('l_m', 'speed_mps', 'density_per_m2'))
        problem = _unusable(l_m, speed, density, tube.length_m)
        if problem:
            raise PlanError(f'{where} holds no usable plan: {problem}. Plan again with vtube plan.')
        plan = make_plan(tube, swarm, options, l_m, speed, density, solved=solved, scene=meta['scene'])
        return replace(plan, provenance=meta['provenance'])


def _unusable(l_m: FloatArray, speed: FloatArray, density: FloatArray, length_m: float) -> str:
    """What makes a plan's numbers unusable on a tube of ``length_m`` ('' when nothing)."""
    if not all(np.all(np.isfinite(a)) for a in (l_m, speed, density)):
        return 'a grid point, speed or density is not a finite number'
    if l_m.size < 2 or l_m[0] != 0.0 or np.any(np.diff(l_m) <= 0.0) or abs(l_m[-1] - length_m) > 1e-9 * length_m:
        return f"its grid does not rise from 0 to the tube's length {length_m:g} m"
    if np.any(speed <= 0.0) or np.any(density <= 0.0):
        return 'a speed or a density is not > 0'
    return ''


def _read_only(values: NDArray[Any]) -> NDArray[Any]:
    """A copy of ``values`` that cannot be written to."""
    frozen = np.array(values, copy=True)
    frozen.flags.writeable = False
    return frozen


def make_plan(
    tube: VirtualTube,
    swarm: SwarmParams,
    options: PlanningOptions,
    l_m: FloatArray,
    speed: FloatArray,
    density: FloatArray,
    *,
    solved: SolveRecord,
    scene: str,
) -> Plan:
    """Wrap planned samples into a [`Plan`][vtube_planning.planning.plan.Plan] with its certificate, active sets and
    objective terms."""
    certificate, active = certify(tube, swarm, options, l_m, speed, density)
    objective = objective_terms(l_m, speed, density, swarm, options, tube)
    return Plan(
        l_m=l_m,
        speed_mps=speed,
        density_per_m2=density,
        half_width_m=np.asarray(tube.half_width(l_m)),
        speed_limit_mps=curvature_speed_limit(tube, planned_limits(swarm, options), l_m),
        time_s=objective['time_s'],
        objective=objective,
        certificate=certificate,
        active=active,
        solved=solved,
        scene=scene,
        swarm=swarm,
        options=options,
        tube_hash=tube.fingerprint(),
    )
