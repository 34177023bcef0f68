"""How a Robotarium run went, from its logged arrays: what the safety filter did, and how the swarm followed its plan.

The arrays are the experiment's trajectory log
([`robotarium_exp.experiment.run_experiment`][robotarium_exp.experiment.run_experiment]): ``t_s``, ``l_m`` (the robots'
centres on the exact tube), ``dxu``, ``r_a_m``, ``density_per_m2``, ``flying``, ``band_held``,
``barrier_correction_mps``; `plan_tracking` also reads a recording of the poses alone (no ``r_a_m``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import NDArray

from vtube_planning.geometry.scene import Scene
from vtube_planning.geometry.width import first_narrowing
from vtube_planning.planning.plan import Plan
from vtube_planning.swarm.metrics import strict_json

Arrays = Mapping[str, NDArray[np.float64]]

EXPANSION_THRESHOLD_M = 0.02
"""The expansion has started once the swarm's mean avoidance radius is this far above its initial value."""


@dataclass(frozen=True)
class FilterSummary:
    """What the safety filter did over a run, and the speed band on the robots.

    Attributes
    ----------
    correction_mean_mps, correction_max_mps
        Per robot-step change of the swarm's command.
    intervention_m
        Its integral over the run, summed over robots (how much the filter had to correct).
    band_share
        Flying robot-steps inside the tube (0 <= l <= L) whose forward speed lies in [v_min, v_max].
    band_share_held
        The same over the steps where the filter kept the band.
    band_dropped_share
        Steps where safety and the band could not both hold (safety won).
    failures
        Steps where the filter found no command at all.
    """

    correction_mean_mps: float
    correction_max_mps: float
    intervention_m: float
    band_share: float
    band_share_held: float
    band_dropped_share: float
    failures: int


def filter_summary(
    arrays: Arrays, v_min: float, v_max: float, length_m: float, dt_s: float, failures: int
) -> FilterSummary:
    """The `FilterSummary` of an experiment's logged arrays; ``failures`` as the filter counted them."""
    correction = arrays['barrier_correction_mps']
    v = arrays['dxu'][:, 0, :]
    in_tube = np.asarray(arrays['flying'], dtype=bool) & (arrays['l_m'] >= 0.0) & (arrays['l_m'] <= length_m)
    in_band = (v >= v_min * (1 - 1e-9)) & (v <= v_max * (1 + 1e-9))
    held = np.asarray(arrays['band_held'], dtype=bool)[:, None] & in_tube
    return FilterSummary(
        correction_mean_mps=float(correction.mean()),
        correction_max_mps=float(correction.max()),
        intervention_m=float(correction.sum() * dt_s),
        band_share=float(in_band[in_tube].mean()) if in_tube.any() else 1.0,
        band_share_held=float(in_band[held].mean()) if held.any() else 1.0,
        band_dropped_share=float(1.0 - arrays['band_held'].mean()),
        failures=int(failures),
    )


def narrowing_start(scene: Scene) -> float:
    """Arc length where the tube first starts to narrow (`vtube_planning.geometry.width.first_narrowing` on its
    width's knots), its length if it never does."""
    narrowing = first_narrowing(*scene.tube.width.knots)
    return narrowing.start_m if narrowing is not None else scene.tube.length_m


def expansion_times(arrays: Arrays, scene: Scene) -> tuple[float | None, float | None]:
    """When the mean r_a first exceeds its initial value by ``EXPANSION_THRESHOLD_M``, and when the first robot
    reaches the narrowing (s; None when it never happens, or, for the expansion, when ``arrays`` hold no
    ``r_a_m``: a recording of the poses alone)."""
    r_a = arrays['r_a_m'].mean(axis=1) if 'r_a_m' in arrays else np.zeros(0)
    expanded = np.flatnonzero(r_a >= r_a[0] + EXPANSION_THRESHOLD_M) if r_a.size else r_a
    narrowing = np.flatnonzero(arrays['l_m'].max(axis=1) >= narrowing_start(scene))
    t = arrays['t_s']
    return (float(t[expanded[0]]) if expanded.size else None, float(t[narrowing[0]]) if narrowing.size else None)


@dataclass(frozen=True)
class PhaseTracking:
    """Relative errors against the plan over the steps of one phase (None: the phase has no step)."""

    steps: int
    density_error_mean: float | None
    density_error_max: float | None
    speed_error_mean: float | None
    speed_error_max: float | None


@dataclass(frozen=True)
class PlanTracking:
    """How a run followed its plan, phase by phase, and when the swarm expanded (`plan_tracking`)."""

    p7_active_m: tuple[float, float] | None
    approach: PhaseTracking
    dip: PhaseTracking
    narrow: PhaseTracking
    expansion_start_s: float | None
    front_at_narrowing_s: float | None

    def phases(self) -> dict[str, PhaseTracking]:
        """The three phases by name, in the order the swarm flies them."""
        return {'approach': self.approach, 'dip': self.dip, 'narrow': self.narrow}

    def to_json(self) -> dict[str, object]:
        """Strict JSON (no NaN or Infinity)."""
        out: dict[str, object] = strict_json(asdict(self))
        return out


def plan_tracking(arrays: Arrays, plan: Plan, scene: Scene) -> PlanTracking:
    """How a run (its logged arrays) followed ``plan``, phase by phase.

    Phases by the arc length l_c of the swarm's centre, over the steps before any robot parks: ``approach``
    before the plan's (p7) binds, ``dip`` while it binds, ``narrow`` after. Per phase, the mean and largest
    relative density error |rho_r - rho*(l_c)| / rho*(l_c) and speed error |v - v*(l_c)| / v*(l_c) (v: the
    flying robots' mean forward speed). ``expansion_start_s`` and ``front_at_narrowing_s``: see
    `expansion_times`.
    """
    swarm = arrays['flying'].all(axis=1)
    center = arrays['l_m'].mean(axis=1)
    active = plan.l_m[plan.active['p7']]
    start, stop = (float(active.min()), float(active.max())) if active.size else (math.inf, math.inf)
    rho_err = np.abs(arrays['density_per_m2'] - plan.density(center)) / plan.density(center)
    speed = arrays['dxu'][:, 0, :].mean(axis=1)
    speed_err = np.abs(speed - plan.speed(center)) / plan.speed(center)

    def phase(mask: NDArray[np.bool_]) -> PhaseTracking:
        return PhaseTracking(
            steps=int(mask.sum()),
            density_error_mean=_finite(rho_err[mask].mean()) if mask.any() else None,
            density_error_max=_finite(rho_err[mask].max()) if mask.any() else None,
            speed_error_mean=_finite(speed_err[mask].mean()) if mask.any() else None,
            speed_error_max=_finite(speed_err[mask].max()) if mask.any() else None,
        )

    expansion, front = expansion_times(arrays, scene)
    return PlanTracking(
        p7_active_m=(start, stop) if active.size else None,
        approach=phase(swarm & (center >= 0.0) & (center < start)),
        dip=phase(swarm & (center >= start) & (center <= stop)),
        narrow=phase(swarm & (center > stop) & (center <= scene.tube.length_m)),
        expansion_start_s=expansion,
        front_at_narrowing_s=front,
    )


def _finite(value: np.floating) -> float | None:
    """A float, or None where it is NaN or infinite (what strict JSON made of it)."""
    number = float(value)
    return number if math.isfinite(number) else None
