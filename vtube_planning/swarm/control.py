"""Parameters of the swarm controller, validated; the law itself is :mod:`vtube_planning.onboard.law`.

The barrier law is the default because it is the one that keeps the expanding swarm inside the tube: the
practical law's wall push is bounded by k_t while the pushes of the neighbours add up, and once r_a exceeds the
narrow half-width its wall band covers the whole section (measured on scenes A-D: tube violations with k_t = 5,
collisions and congestion with k_t = 15 or 40).
"""

from __future__ import annotations

from dataclasses import dataclass

from vtube_planning._validate import is_positive, is_real
from vtube_planning.errors import ParamsError
from vtube_planning.onboard import (
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
from vtube_planning.params import SwarmParams

# ---------------------------------------------------------------------- parameters


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
    kdtree_above
        Use a k-d tree for neighbours above this many robots, all pairs below (default: the measured crossover
        :data:`~vtube_planning.onboard.params.KDTREE_ABOVE`; both give the same law).
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
    kdtree_above: int = KDTREE_ABOVE

    def __post_init__(self) -> None:
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
            kdtree_above=self.kdtree_above,
        )
