"""Swarm parameters of the paper (Table 1) and the quantities derived from them.

The defaults are Table 1 exactly as printed (``docs/design.md``). Two printed values disagree with the paper's own
formulas (``docs/theory.md`` §7.1):

* ``rho_max``: the table says 0.9974 robots/m^2 while the printed formula ``1/r_p^2`` gives 11.11. The table value
  is kept; :meth:`SwarmParams.rho_max_variants` lists the candidate formulas for ablations.
* ``a_rho``: formula (p8) is negative, which makes (p6)/(p7) infeasible as printed. Its magnitude is used
  (resolution A2), 0.5524 robots/m^2/s for Table 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from vtube_planning._validate import is_positive, is_real
from vtube_planning.errors import ParamsError


@dataclass(frozen=True)
class SwarmParams:
    """Parameters of a speed-constrained swarm (paper Table 1, SI units).

    Parameters
    ----------
    n_robots
        Number of robots N (>= 1).
    v_min_mps, v_max_mps
        Speed bounds of every robot, ``0 < v_min <= v_max``, in m/s.
    a_v_mps2
        Tangential acceleration limit a_v, in m/s^2.
    a_n_mps2
        Normal (centripetal) acceleration limit a_n, in m/s^2.
    r_p_m, r_s_m, r_a_m
        Physical, safety and (initial) avoidance radius, ``0 < r_p <= r_s <= r_a``, in m.
    rho_d_per_m2
        Desired density rho_d of the objective, in robots/m^2.
    rho_max_per_m2
        Maximum density rho_max of constraint (p5), in robots/m^2.
    """

    n_robots: int = 20
    v_min_mps: float = 2.0
    v_max_mps: float = 5.0
    a_v_mps2: float = 1.0
    a_n_mps2: float = 1.0
    r_p_m: float = 0.3
    r_s_m: float = 0.4
    r_a_m: float = 0.8
    rho_d_per_m2: float = 0.1989
    rho_max_per_m2: float = 0.9974

    def __post_init__(self) -> None:
        if isinstance(self.n_robots, bool) or not isinstance(self.n_robots, int) or self.n_robots < 1:
            msg = f'n_robots must be an integer >= 1; got {self.n_robots!r}. Give the swarm size as a whole number.'
            raise ParamsError(msg)
        for f in fields(self):
            value = getattr(self, f.name)
            if not is_positive(value):
                msg = f'{f.name} must be a finite number > 0; got {value!r}.'
                raise ParamsError(msg)
        if self.v_min_mps > self.v_max_mps:
            msg = (
                f'v_min_mps ({self.v_min_mps}) exceeds v_max_mps ({self.v_max_mps}); '
                'a speed-constrained robot needs 0 < v_min <= v_max.'
            )
            raise ParamsError(msg)
        if not self.r_p_m <= self.r_s_m <= self.r_a_m:
            msg = (
                f'radii must satisfy r_p <= r_s <= r_a; got r_p_m={self.r_p_m}, r_s_m={self.r_s_m}, '
                f'r_a_m={self.r_a_m}. The safety radius encloses the robot and the avoidance radius encloses both.'
            )
            raise ParamsError(msg)
        if self.rho_d_per_m2 > self.rho_max_per_m2:
            msg = (
                f'rho_d_per_m2 ({self.rho_d_per_m2}) exceeds rho_max_per_m2 ({self.rho_max_per_m2}); '
                'the desired density must be reachable under constraint (p5).'
            )
            raise ParamsError(msg)

    @property
    def n_side(self) -> int:
        """n = ceil(sqrt(N)): robots per side of the square packing of Assumption 2."""
        return math.isqrt(self.n_robots - 1) + 1

    @property
    def a_rho(self) -> float:
        """Density rate limit |a_rho| = sqrt(2) N v_max / (4 n^3 r_a^3) of (p8), robots/m^2/s (magnitude, A2)."""
        return math.sqrt(2.0) * self.n_robots * self.v_max_mps / (4.0 * self.n_side**3 * self.r_a_m**3)

    @property
    def rho_packing(self) -> float:
        """Density N / (2 n r_a)^2 of the square packing of Assumption 2 (robots/m^2), a natural rho_0 (A15)."""
        return self.n_robots / (2.0 * self.n_side * self.r_a_m) ** 2

    def rho_max_variants(self) -> dict[str, float]:
        """Candidate values of rho_max (robots/m^2): the table's and the formulas of ``docs/theory.md`` §7.1.

        Keys: ``table`` (the configured value), ``printed_formula`` 1/r_p^2, ``square_safety`` 1/(4 r_s^2) (Assumption
        2 read literally), ``square_physical`` 1/(4 r_p^2), ``circle_safety`` 1/(2 pi r_s^2) (matches Table 1's
        0.9974 to four digits with two digits transposed).
        """
        return {
            'table': self.rho_max_per_m2,
            'printed_formula': 1.0 / self.r_p_m**2,
            'square_safety': 1.0 / (4.0 * self.r_s_m**2),
            'square_physical': 1.0 / (4.0 * self.r_p_m**2),
            'circle_safety': 1.0 / (2.0 * math.pi * self.r_s_m**2),
        }


PREDICTIVE_MODELS = ('local_width', 'rigid_shift', 'none')
"""The two readings of the predictive density constraint (p7), ``docs/theory.md`` §7 A6 and §8.3, and ``'none'``,
(p7) left out (the study's ablation: a plan without the pre-expansion it forces)."""


@dataclass(frozen=True)
class PlanningOptions:
    """Options of the speed and density planner that belong to a scene.

    Parameters
    ----------
    grid_step_m
        Arc-length step of the planning grid, > 0.
    density_weight
        Weight mu of the density term of the objective (p1); 1 is the paper's unweighted sum (A5).
    predictive_model
        Reading of (p7): ``'local_width'`` rho_f = rho lambda(l) / lambda(l + dl), or ``'rigid_shift'`` of the
        swarm's whole footprint (``docs/theory.md`` §8.3); ``'none'`` leaves (p7) out.
    lookahead_m
        Look-ahead distance dl of (p7), > 0 (the paper leaves it unspecified, A6).
    v0_mps
        Initial average forward speed v_a(0); None means v_min (A15).
    rho0_per_m2
        Initial density rho_a(0); None means the square packing N / (2 n r_a)^2 of Assumption 2 (A15).
    refinement
        Split every grid interval where (p3), (p4), (p6) or (p7) binds into this many and plan again on that grid,
        an integer >= 1 (1: the uniform grid only). The plan's J converges to the continuous optimum in the grid
        step; refining where the constraints bind shrinks that error at a fraction of a uniformly finer grid's
        size (``python -m benchmarks.plan_bench`` prints both).
    """

    grid_step_m: float = 0.25
    density_weight: float = 1.0
    predictive_model: str = 'local_width'
    lookahead_m: float = 4.0
    v0_mps: float | None = None
    rho0_per_m2: float | None = None
    refinement: int = 1

    def __post_init__(self) -> None:
        for name in ('grid_step_m', 'lookahead_m', 'v0_mps', 'rho0_per_m2'):
            value = getattr(self, name)
            if value is None and name in ('v0_mps', 'rho0_per_m2'):
                continue
            if not is_positive(value):
                msg = f'planning option {name} must be a finite number > 0; got {value!r}.'
                raise ParamsError(msg)
        weight = self.density_weight
        if not is_real(weight) or weight < 0:
            msg = f'planning option density_weight must be a finite number >= 0; got {weight!r}.'
            raise ParamsError(msg)
        if isinstance(self.refinement, bool) or not isinstance(self.refinement, int) or self.refinement < 1:
            msg = f'planning option refinement must be a whole number >= 1; got {self.refinement!r}.'
            raise ParamsError(msg)
        if self.predictive_model not in PREDICTIVE_MODELS:
            msg = f'planning option predictive_model must be one of {PREDICTIVE_MODELS}; got {self.predictive_model!r}.'
            raise ParamsError(msg)
