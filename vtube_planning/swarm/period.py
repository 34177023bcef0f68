"""One control period of the simulated swarm: the controller's commands from what the faults let it see, and the
robots' velocities over the period (the command that reaches them, the acceleration limits, a failed robot)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.onboard import Projection, SwarmStep, swarm_density
from vtube_planning.params import SwarmParams
from vtube_planning.swarm.dynamics import limit_acceleration
from vtube_planning.swarm.faults import Faults
from vtube_planning.swarm.foresight import Foresight
from vtube_planning.swarm.replanner import Replanner

FloatArray = NDArray[np.float64]
Baseline = Callable[[FloatArray, FloatArray, Projection], FloatArray]
"""Another swarm law: ``baseline(positions, velocities, projection) -> commands``, all (2, N)."""


@dataclass
class SimulatedPeriod:
    """What one run flies each control period with: the tube, the swarm, the period and whether the acceleration
    limits apply, the controller (the swarm step, or a baseline, and the foresight over either), the replanner and
    the faults."""

    tube: VirtualTube
    swarm: SwarmParams
    dt_s: float
    acceleration_limits: bool
    stepper: SwarmStep
    baseline: Baseline | None
    replanner: Replanner | None
    faults: Faults
    foresight: Foresight | None = None

    def command(
        self, step: int, positions: FloatArray, projection: Projection, velocity: FloatArray
    ) -> tuple[FloatArray, float, FloatArray]:
        """The controller's velocity commands, the measured density and the avoidance radii at control period
        ``step``, from the true ``positions`` and their ``projection`` as the faults let it see them."""
        seen, view = self.faults.observe(self.tube, positions, projection)
        if self.baseline is not None:
            commanded = self.baseline(seen, velocity, view)
            return (
                self._foreseen(seen, velocity, commanded),
                swarm_density(self.tube, view.l_m, self.swarm.r_a_m),
                self.stepper.r_a,
            )
        result = self.stepper(seen, self.dt_s, view, self.faults.heard(seen))
        if self.replanner is not None:
            profile = self.replanner(step, view, velocity, float(result.density_per_m2), self.faults.working)
            if profile is not None:
                self.stepper.plan = profile
        return self._foreseen(seen, velocity, result.velocity), result.density_per_m2, result.r_a_m

    def _foreseen(self, seen: FloatArray, velocity: FloatArray, commanded: FloatArray) -> FloatArray:
        """The command the foresight lets through (all of ``commanded`` without one)."""
        if self.foresight is None:
            return commanded
        return self.foresight(seen, velocity, commanded, self.dt_s)

    def next_velocity(self, velocity: FloatArray, commanded: FloatArray, l_m: FloatArray) -> FloatArray:
        """The robots' velocities over the next period: the command that reaches them, held to the acceleration
        limits when they apply, the failed robot's own."""
        commanded = self.faults.delayed(commanded)
        if self.acceleration_limits:
            swarm = self.swarm
            velocity = limit_acceleration(velocity, commanded, swarm.a_v_mps2, swarm.a_n_mps2, self.dt_s)
        else:
            velocity = commanded
        return self.faults.failed(velocity, l_m)
