"""One period of the tube experiment on a Robotarium, and the loop around it: the bundled experiment and the
submitted file run this same code (:mod:`submission.builder` inlines it).

Each period:

1. poses -> control points p + d e_theta (:mod:`unicycle_mapping`);
2. the swarm step (:class:`~vtube_planning.swarm.step.SwarmStep`) on the control points: the plan's forward term
   (or a constant speed), avoidance, tube keeping, sat, (a3); robots past the exit drive to parking slots;
3. the single-integrator barrier certificate (whichever the caller gives: ours, or the testbed's own);
4. the near-identity map to [v; omega] and uniform wheel scaling (curvature kept, no per-wheel clipping left for
   the testbed to do).

The loop (:func:`fly`) hands the commands to ``set_velocities`` and calls ``step()`` until every robot has parked
or the step limit; the caller records each period as it likes. It needs numpy only and uses the Robotarium
object through ``get_poses``, ``set_velocities`` and ``step``, so any ``rps`` implementation runs it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from unicycle_mapping.mapping import si_to_uni, uni_to_si_states
from unicycle_mapping.wheels import scale_to_wheel_limits
from vtube_planning.geometry.projection import SampledTube
from vtube_planning.swarm.step import PlanProfile, StepParams, StepResult, SwarmStep

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Period:
    """One control period: the poses, control points, the swarm step, the certified velocities, the commands."""

    poses: FloatArray
    points_m: FloatArray
    step: StepResult
    safe_mps: FloatArray
    dxu: FloatArray

    @property
    def barrier_correction_mps(self) -> FloatArray:
        """How much the barrier certificate changed each robot's velocity, (N,)."""
        return np.hypot(*(self.safe_mps - self.step.velocity))


@dataclass(frozen=True)
class Wheels:
    """The robot's drive: axle length, wheel radius, wheel speed limit (from ``RobotariumSpec``)."""

    base_length_m: float
    wheel_radius_m: float
    max_wheel_speed_radps: float


class Flight:
    """The experiment's controller: control points, swarm step, barrier, map, wheel scaling.

    Parameters
    ----------
    stepper
        The swarm step with its plan, tube and parking slots.
    barrier
        ``barrier(dxi, points) -> dxi`` (single-integrator certificate), or None.
    projection_distance_m
        d of the near-identity map.
    wheels
        The drive's limits.
    """

    def __init__(
        self,
        stepper: SwarmStep,
        barrier: Callable[[FloatArray, FloatArray], FloatArray] | None,
        projection_distance_m: float,
        wheels: Wheels,
    ) -> None:
        self.stepper = stepper
        self.barrier = barrier
        self.d = float(projection_distance_m)
        self.wheels = wheels

    def __call__(self, poses: FloatArray, dt_s: float) -> Period:
        """The commands for robots at ``poses`` (3, N); advances the swarm's state by ``dt_s``."""
        points = uni_to_si_states(poses, self.d)
        step = self.stepper(points, dt_s)
        safe = self.barrier(step.velocity, points) if self.barrier is not None else step.velocity
        w = self.wheels
        dxu, _ = scale_to_wheel_limits(
            si_to_uni(safe, poses, self.d), w.base_length_m, w.wheel_radius_m, w.max_wheel_speed_radps
        )
        return Period(poses, points, step, safe, dxu)


def build_flight(data: dict[str, Any], barrier: Callable[[FloatArray, FloatArray], FloatArray] | None) -> Flight:
    """The flight described by ``data`` (:func:`robotarium_exp.experiment.flight_data`, a submission's ``DATA``)."""
    tube = SampledTube(**data['tube'])
    plan = None
    if data['planned']:
        plan = PlanProfile(**{key: np.asarray(value, dtype=float) for key, value in data['plan'].items()})
    stepper = SwarmStep(
        tube,
        StepParams(**data['step']),
        int(data['n_robots']),
        plan=plan,
        constant_speed_mps=float(data['constant_speed_mps']),
        parking_slots=np.asarray(data['parking_slots'], dtype=float),
    )
    return Flight(stepper, barrier, float(data['projection_distance_m']), Wheels(**data['wheels']))


def fly(
    robotarium: Any, flight: Flight, dt_s: float, max_steps: int, record: Callable[[int, Period], None]
) -> tuple[bool, int]:
    """Run ``flight`` on ``robotarium`` until every robot has parked (True) or ``max_steps`` (False).

    ``record(step, period)`` sees every period before its commands are sent. Returns (completed, periods run).
    """
    n = int(flight.stepper.r_a.size)
    for step in range(max_steps):
        period = flight(robotarium.get_poses(), dt_s)
        record(step, period)
        if period.step.done:
            return True, step + 1
        robotarium.set_velocities(np.arange(n), period.dxu)
        robotarium.step()
    return False, max_steps
