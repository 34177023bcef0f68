"""Replanning in flight: the rest of the tube planned again every few control periods from the measured state."""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vtube_planning.errors import PlanError
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.onboard import PlanProfile, Projection
from vtube_planning.planning.plan import Plan, SwarmState
from vtube_planning.planning.planner import replan

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ReplanCall:
    """One replanning: the control period, the arc length planned from, its wall time, and its error ('' when the
    new plan was taken)."""

    step: int
    from_m: float
    wall_ms: float
    error: str


class Replanner:
    """Replans a flight every ``every`` control periods from the swarm's measured state, and keeps the record."""

    def __init__(self, plan: Plan, tube: VirtualTube, every: int) -> None:
        self.plan, self.tube, self.every = plan, tube, every
        self.profiles = [plan.profile]
        self.calls: list[ReplanCall] = []

    def __call__(
        self, step: int, view: Projection, velocity: FloatArray, density: float, working: NDArray[np.bool_]
    ) -> PlanProfile | None:
        """The new plan's profile at a replanning step (None otherwise, or when replanning failed), from what the
        controller sees (``view``), the robots' velocities and the measured density."""
        if step == 0 or step % self.every:
            return None
        l_m = view.l_m
        flying = working & (l_m < self.tube.length_m)
        if not flying.any():
            return None
        forward_mps = np.einsum('ij,ij->j', velocity, view.tangent)
        start = max(0.0, float(l_m[flying].mean()))
        if start > self.tube.length_m - 2.0 * self.plan.options.grid_step_m:
            return None  # the swarm is leaving: nothing left to plan
        count = int(working.sum())
        state = SwarmState(start, float(forward_mps[flying].mean()), density, None if working.all() else count)
        started = time.perf_counter()
        try:
            rest = replan(self.plan, state, self.tube)
        except PlanError as err:
            self.calls.append(ReplanCall(step, start, _ms_since(started), str(err)))
            return None
        self.calls.append(ReplanCall(step, start, _ms_since(started), ''))
        self.profiles.append(rest.profile)
        return rest.profile

    def flown(self) -> PlanProfile:
        """The plan as flown: each replanned profile replaces the one before from the arc length it starts at."""
        l_m, slowness, density = self.profiles[0].l_m, self.profiles[0].slowness_spm, self.profiles[0].density_per_m2
        for later in self.profiles[1:]:
            keep = l_m < later.l_m[0]
            l_m = np.concatenate([l_m[keep], later.l_m])
            slowness = np.concatenate([slowness[keep], later.slowness_spm])
            density = np.concatenate([density[keep], later.density_per_m2])
        return PlanProfile(l_m, slowness, density)


def _ms_since(started: float) -> float:
    """Milliseconds since the ``time.perf_counter()`` reading ``started``."""
    return 1e3 * (time.perf_counter() - started)
