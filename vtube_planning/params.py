"""The configuration of a run: the swarm's parameters (paper Table 1), the planner's options, the controller's gains.

The defaults of [`SwarmParams`][vtube_planning.params.SwarmParams] are Table 1 exactly as printed (``docs/design.md``).
Two printed values disagree with the paper's own formulas (``docs/theory.md`` §7.1):

* ``rho_max``: the table says 0.9974 robots/m^2 while the printed formula ``1/r_p^2`` gives 11.11. The table value
  is kept; [`SwarmParams.rho_max_variants`][vtube_planning.params.SwarmParams.rho_max_variants] lists the candidate
  formulas for ablations.
* ``a_rho``: formula (p8) is negative, which makes (p6)/(p7) infeasible as printed. Its magnitude is used
  (resolution A2), 0.5524 robots/m^2/s for Table 1.

[`ControlParams`][vtube_planning.params.ControlParams] defaults to the barrier law: the practical law's wall push is
bounded by k_t while the neighbours' pushes add up, so it lets the expanding swarm out of the tube (``docs/theory.md``
§2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from vtube_planning._validate import is_positive, is_real
from vtube_planning.errors import ParamsError
from vtube_planning.onboard.params import (
    DENSITY_PADDINGS,
    KDTREE_ABOVE,
    LAWS,
    PLAN_AT,
    SATURATIONS,
    DensityPadding,
    Law,
    PlanAt,
    Saturation,
    StepParams,
)


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

OBJECTIVES = ('centre', 'last_out')
"""What the planner's time term models: ``'centre'`` the swarm centre's traversal time, the paper's (p1);
``'last_out'`` the measured passing time, first robot in to last robot out (``docs/theory.md`` §8.7)."""

FREEDOMS = ('paper', 'relaxed')
"""What the plan is held to: ``'paper'`` (p2)-(p7) from v_min, as the paper plans; ``'relaxed'`` the freedom the
unplanned swarm has in the paper's robot model, which holds no robot to (3), (4): the plan starts at v_max and
(p3), (p4) are left out (``docs/theory.md`` §8.8)."""


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
    objective
        One of ``OBJECTIVES``: ``'centre'`` minimises the centre's traversal time, the paper's (p1); ``'last_out'``
        adds the swarm's half-extents N / (4 lambda rho) over the speed at the entrance and the exit, so that the
        time term models the measured passing time, first robot in to last robot out (``docs/theory.md`` §8.7).
    freedom
        One of ``FREEDOMS``: ``'paper'`` plans under (p2)-(p7) from v_min (the paper); ``'relaxed'`` starts at v_max
        (unless ``v0_mps`` is given) and leaves (p3), (p4) out, the freedom of the unplanned swarm in the paper's robot
        model (``docs/theory.md`` §8.8).
    braking_room
        Keep the planned spacing 1 / sqrt(rho) at least 2 r_s plus the distance (v^2 - v_min^2) / (2 a_v) a robot
        needs to brake from the planned speed v to v_min (``docs/theory.md`` §8.9). False (the default): the paper's
        constraints only.
    """

    grid_step_m: float = 0.25
    density_weight: float = 1.0
    predictive_model: str = 'local_width'
    lookahead_m: float = 4.0
    v0_mps: float | None = None
    rho0_per_m2: float | None = None
    refinement: int = 1
    objective: str = 'centre'
    freedom: str = 'paper'
    braking_room: bool = False

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
        if self.objective not in OBJECTIVES:
            msg = f'planning option objective must be one of {OBJECTIVES}; got {self.objective!r}.'
            raise ParamsError(msg)
        if not isinstance(self.braking_room, bool):
            msg = f'planning option braking_room must be true or false; got {self.braking_room!r}.'
            raise ParamsError(msg)
        if self.freedom not in FREEDOMS:
            msg = f'planning option freedom must be one of {FREEDOMS}; got {self.freedom!r}.'
            raise ParamsError(msg)


@dataclass(frozen=True)
class ControlParams:
    """Gains and options of the swarm controller.

    Parameters
    ----------
    avoidance_gain, keeping_gain
        Gains k of the inter-robot avoidance and tube-keeping terms: m^3/s in the barrier law (V = k sigma / D,
        the group's code uses 1), m/s in the practical law (its largest push per neighbour or wall).
    k_ra_m3ps
        Gain of the avoidance-radius law (a3), m/s per robot/m^2, >= 0; 0 switches (a3) off (r_a keeps its initial
        value unless ``feedforward`` raises it).
    r_a_max_m
        Cap of the avoidance radius (resolution A9); None means three times the initial r_a.
    feedforward
        Floor r_a,i by 1/sqrt(rho*(l_i)) - r_s, the lattice spacing that realises the planned density (§2.8).
    law
        ``'practical'`` (sigma-weighted, bounded) or ``'barrier'`` (gradients of the barrier functions).
    saturation
        ``'radial'``: the paper's sat of the whole command into [v_min, v_max], which can point a robot backwards
        (A10); ``'forward'``: v* t_c + sat(v_m + v_xy, v* - v_min) capped at v_max, never backwards.
    density_padding
        The measured density N / S pads the swarm's footprint S at both ends by ``'initial'`` r_a (A7) or by the
        ``'current'`` mean r_a.
    plan_at
        Read the plan at each robot's arc length (``'robot'``, the paper) or at the swarm centre's (``'center'``,
        ``docs/theory.md`` A16): with ``'robot'`` a planned slow-down reaches the front first and compresses the
        swarm just where the plan lowers its density.
    stretch_gain_mps
        Density tracking along the tube, m/s, >= 0 (not in the paper; ``docs/theory.md`` §2.9): a robot ahead of
        the swarm's centre goes faster by up to this, one behind it slower, in proportion to the swarm's relative
        density error, so that a swarm denser than the plan lengthens and a sparser one closes up. 0 (the default):
        off, the paper's law.
    kdtree_above
        Use a k-d tree for neighbours above this many robots, all pairs below (default: the measured crossover
        `KDTREE_ABOVE`; both give the same law).
    compensate_delay_steps, compensate_lag_s
        The command delay (control periods, >= 0) and first-order lag (s, >= 0) to compensate: the controller acts
        on where each robot will be when its command arrives, predicted from the commands already sent
        ([`CommandPredictor`][vtube_planning.onboard.delay.CommandPredictor]). Both 0 (the default): it acts on where
        they are.
    foresight_s
        Horizon T (s) of the foresight, the safety layer of robots that obey (2)-(4) (`vtube_planning.swarm.foresight`,
        ``docs/theory.md`` §11): each robot predicts its path under the acceleration limits for T seconds and
        replaces the law's command where that path meets a wall or a neighbour's. 0 (the default): the law alone,
        as the paper flies it.
    """

    avoidance_gain: float = 1.0
    keeping_gain: float = 1.0
    k_ra_m3ps: float = 5.0
    r_a_max_m: float | None = None
    feedforward: bool = False
    law: Law = 'barrier'
    saturation: Saturation = 'radial'
    density_padding: DensityPadding = 'initial'
    plan_at: PlanAt = 'robot'
    stretch_gain_mps: float = 0.0
    kdtree_above: int = KDTREE_ABOVE
    compensate_delay_steps: float = 0.0
    compensate_lag_s: float = 0.0
    foresight_s: float = 0.0

    def __post_init__(self) -> None:
        if not is_real(self.foresight_s) or self.foresight_s < 0:
            msg = f'control foresight_s must be a finite number >= 0 (0: the law alone); got {self.foresight_s!r}.'
            raise ParamsError(msg)
        for name in ('compensate_delay_steps', 'compensate_lag_s'):
            value = getattr(self, name)
            if not is_real(value) or value < 0:
                msg = f'control {name} must be a finite number >= 0 (0: nothing to compensate); got {value!r}.'
                raise ParamsError(msg)
        if not is_real(self.stretch_gain_mps) or self.stretch_gain_mps < 0:
            msg = f'control stretch_gain_mps must be a finite number >= 0 (0: off); got {self.stretch_gain_mps!r}.'
            raise ParamsError(msg)
        for name in ('avoidance_gain', 'keeping_gain'):
            if not is_positive(getattr(self, name)):
                msg = f'control {name} must be a finite number > 0; got {getattr(self, name)!r}.'
                raise ParamsError(msg)
        if not is_real(self.k_ra_m3ps) or self.k_ra_m3ps < 0:
            msg = f'control k_ra_m3ps must be a finite number >= 0 (0: (a3) off); got {self.k_ra_m3ps!r}.'
            raise ParamsError(msg)
        if self.r_a_max_m is not None and not is_positive(self.r_a_max_m):
            msg = f'control r_a_max_m must be a finite number > 0 or omitted; got {self.r_a_max_m!r}.'
            raise ParamsError(msg)
        if self.law not in LAWS:
            msg = f'control law must be one of {LAWS}; got {self.law!r}.'
            raise ParamsError(msg)
        if self.saturation not in SATURATIONS:
            msg = f'control saturation must be one of {SATURATIONS}; got {self.saturation!r}.'
            raise ParamsError(msg)
        if self.density_padding not in DENSITY_PADDINGS:
            msg = f'control density_padding must be one of {DENSITY_PADDINGS}; got {self.density_padding!r}.'
            raise ParamsError(msg)
        if self.plan_at not in PLAN_AT:
            msg = f'control plan_at must be one of {PLAN_AT}; got {self.plan_at!r}.'
            raise ParamsError(msg)
        if not isinstance(self.feedforward, bool):
            msg = f'control feedforward must be true or false; got {self.feedforward!r}.'
            raise ParamsError(msg)
        if isinstance(self.kdtree_above, bool) or not isinstance(self.kdtree_above, int) or self.kdtree_above < 0:
            msg = f'control kdtree_above must be an integer >= 0; got {self.kdtree_above!r}.'
            raise ParamsError(msg)

    def radius_cap(self, swarm: SwarmParams) -> float:
        """The largest avoidance radius, m."""
        cap = 3.0 * swarm.r_a_m if self.r_a_max_m is None else float(self.r_a_max_m)
        if cap < swarm.r_a_m:
            msg = f'control r_a_max_m ({cap}) is below the initial avoidance radius r_a_m ({swarm.r_a_m}); raise it.'
            raise ParamsError(msg)
        return cap

    def step_params(self, swarm: SwarmParams) -> StepParams:
        """What one control period needs of these gains and the swarm's parameters."""
        if swarm.r_a_m <= swarm.r_s_m:
            msg = (
                f'the controller needs r_a_m > r_s_m (its interaction bands run from r_s to r_a); got '
                f'r_s_m = {swarm.r_s_m}, r_a_m = {swarm.r_a_m}.'
            )
            raise ParamsError(msg)
        return StepParams(
            r_s_m=swarm.r_s_m,
            r_a_m=swarm.r_a_m,
            r_a_max_m=self.radius_cap(swarm),
            v_min_mps=swarm.v_min_mps,
            v_max_mps=swarm.v_max_mps,
            law=self.law,
            saturation=self.saturation,
            density_padding=self.density_padding,
            avoidance_gain=self.avoidance_gain,
            keeping_gain=self.keeping_gain,
            k_ra_m3ps=self.k_ra_m3ps,
            feedforward=self.feedforward,
            plan_at=self.plan_at,
            stretch_gain_mps=float(self.stretch_gain_mps),
            kdtree_above=self.kdtree_above,
            compensate_delay_steps=float(self.compensate_delay_steps),
            compensate_lag_s=float(self.compensate_lag_s),
        )
