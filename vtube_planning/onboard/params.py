"""What one control period is given: :class:`StepParams`, and the modes it chooses between (``Literal`` types)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, get_args

Law = Literal['practical', 'barrier']
"""The magnitudes of the pushes: the practical law of [b17], or the barrier law's gradients (``docs/theory.md``
§2.4)."""
DensityPadding = Literal['initial', 'current']
"""How far the measured footprint extends beyond the last and the front robot: the initial r_a (fixed cells of
Assumption 2, A7), or the swarm's current mean r_a (cells that grow with (a3))."""
Saturation = Literal['radial', 'forward']
"""How the command meets the speed band: the paper's radial sat of the whole sum (A10: it can point backwards), or
the forward-progress form v* t_c + sat(v_m + v_xy, v* - v_min) capped at v_max (``docs/theory.md`` §2.7), which keeps every robot moving forward at v_min or more."""
PlanAt = Literal['robot', 'center']
"""Where every robot reads the plan: at its own arc length l_i, or at the swarm centre's (``docs/theory.md`` A16)."""

LAWS: tuple[Law, ...] = get_args(Law)
DENSITY_PADDINGS: tuple[DensityPadding, ...] = get_args(DensityPadding)
SATURATIONS: tuple[Saturation, ...] = get_args(Saturation)
PLAN_AT: tuple[PlanAt, ...] = get_args(PlanAt)

KDTREE_ABOVE = 64
"""Swarms of more robots find their neighbours with a k-d tree, smaller ones test all pairs (the crossover is
measured by ``benchmarks/sim_bench.py``)."""


@dataclass(frozen=True)
class StepParams:
    """The numbers one control period needs (made and validated by ``ControlParams.step_params(swarm)``).

    Attributes
    ----------
    r_s_m
        Safety radius r_s.
    r_a_m
        Initial avoidance radius; also the padding of the density measure at both ends of the swarm (A7).
    r_a_max_m
        Cap of the avoidance radius (A9).
    v_min_mps, v_max_mps
        The speed band of sat.
    law
        ``'barrier'`` or ``'practical'``, :data:`Law`.
    saturation
        ``'radial'`` (the paper's sat) or ``'forward'`` (the forward-progress form), :data:`Saturation`.
    density_padding
        Pad the measured footprint by the initial r_a or by the current mean r_a, :data:`DensityPadding`.
    avoidance_gain, keeping_gain
        Gains of the avoidance and tube-keeping terms.
    k_ra_m3ps
        Gain of (a3).
    feedforward
        Floor r_a by ``1/sqrt(rho*) - r_s``.
    plan_at
        ``'robot'``: every robot reads v* and rho* at its own arc length (the paper); ``'center'``: at the mean arc
        length of the swarm's robots, for which the plan is made (A16); :data:`PlanAt`.
    stretch_gain_mps
        Density tracking along the tube (``docs/theory.md`` §2.9): forward speeds spread by up to this much over the
        swarm's length, by its relative density error; 0: off (the paper's law).
    kdtree_above
        Find neighbours with a k-d tree above this many robots, all pairs below.
    compensate_delay_steps, compensate_lag_s
        The command delay (control periods) and lag (s) the step compensates by acting on where the robots will be
        (:class:`~vtube_planning.onboard.delay.CommandPredictor`); both 0: it acts on where they are.
    """

    r_s_m: float
    r_a_m: float
    r_a_max_m: float
    v_min_mps: float
    v_max_mps: float
    law: Law = 'barrier'
    saturation: Saturation = 'radial'
    density_padding: DensityPadding = 'initial'
    avoidance_gain: float = 1.0
    keeping_gain: float = 1.0
    k_ra_m3ps: float = 5.0
    feedforward: bool = False
    plan_at: PlanAt = 'robot'
    stretch_gain_mps: float = 0.0
    kdtree_above: int = KDTREE_ABOVE
    compensate_delay_steps: float = 0.0
    compensate_lag_s: float = 0.0

    @property
    def compensates(self) -> bool:
        """Whether the step acts on predicted positions (a delay or a lag to compensate)."""
        return self.compensate_delay_steps > 0.0 or self.compensate_lag_s > 0.0
