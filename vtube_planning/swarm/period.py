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
from vtube_planning.swarm.faults import Faults
from vtube_planning.swarm.replanner import Replanner

FloatArray = NDArray[np.float64]
Baseline = Callable[[FloatArray, FloatArray, Projection], FloatArray]
"""Another swarm law: ``baseline(positions, velocities, projection) -> commands``, all (2, N)."""


@dataclass
class SimulatedPeriod:
    """What one run flies each control period with: the tube, the swarm, the period and whether the acceleration
    limits apply, the controller (the swarm step, or a baseline), the replanner and the faults."""

    tube: VirtualTube
    swarm: SwarmParams
    dt_s: float
    acceleration_limits: bool
    stepper: SwarmStep
    baseline: Baseline | None
    replanner: Replanner | None
    faults: Faults

    def command(
        self, step: int, positions: FloatArray, projection: Projection, velocity: FloatArray
    ) -> tuple[FloatArray, float, FloatArray]:
        """The controller's velocity commands, the measured density and the avoidance radii at control period
        ``step``, from the true ``positions`` and their ``projection`` as the faults let it see them."""
        seen, view = self.faults.observe(self.tube, positions, projection)
        if self.baseline is not None:
            commanded = self.baseline(seen, velocity, view)
            return commanded, swarm_density(self.tube, view.l_m, self.swarm.r_a_m), self.stepper.r_a
        result = self.stepper(seen, self.dt_s, view, self.faults.heard(seen))
        if self.replanner is not None:
            profile = self.replanner(step, view, velocity, float(result.density_per_m2), self.faults.working)
            if profile is not None:
                self.stepper.plan = profile
        return result.velocity, result.density_per_m2, result.r_a_m

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


def limit_acceleration(velocity: FloatArray, command: FloatArray, a_v: float, a_n: float, dt_s: float) -> FloatArray:
    """The velocity after one step of following ``command`` with |d|v|/dt| <= a_v and |v| |dtheta/dt| <= a_n."""
    speed = np.hypot(velocity[0], velocity[1])
    target = np.hypot(command[0], command[1])
    new_speed = speed + np.clip(target - speed, -a_v * dt_s, a_v * dt_s)
    heading = np.arctan2(velocity[1], velocity[0])
    turn = np.angle(np.exp(1j * (np.arctan2(command[1], command[0]) - heading)))
    max_turn = a_n * dt_s / np.maximum(new_speed, 1e-12)
    heading = heading + np.clip(turn, -max_turn, max_turn)
    velocity_after: FloatArray = new_speed * np.vstack([np.cos(heading), np.sin(heading)])
    return velocity_after
