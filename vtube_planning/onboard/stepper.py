"""One control period of the swarm, with its state: :class:`SwarmStep`, the one implementation.

The simulator, the bundled Robotarium experiment and the file submitted to the testbed all call it. Each period it
projects the robots onto the tube, measures the swarm's density once (A7-A8), commands the law (s1), and with a plan
advances the avoidance radii by (a3). Robots past the exit either keep flying the law (the paper's study) or, given
parking slots, drive to a slot and leave the swarm: its avoidance and its density count only the robots still
flying the tube (the safety filter keeps everyone apart).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vtube_planning.onboard.delay import CommandPredictor
from vtube_planning.onboard.density import swarm_density
from vtube_planning.onboard.law import Command, velocity_command
from vtube_planning.onboard.params import StepParams
from vtube_planning.onboard.parking import Parking
from vtube_planning.onboard.profile import PlanProfile
from vtube_planning.onboard.projection import Projection
from vtube_planning.onboard.radius import next_radius
from vtube_planning.onboard.stretch import stretched_speed
from vtube_planning.onboard.tube import StepTube

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class StepResult:
    """One control period: the command, what it was computed from, and the swarm's state.

    ``velocity`` is the single-integrator command (2, N) (parked robots: towards their slot); ``command`` its
    parts; ``r_a_m`` the radii the command used (the step then advanced them by (a3)); ``parked`` the robots that
    have left the tube and drive to a slot; ``done`` when every robot has exited (no slots) or parked.
    """

    velocity: FloatArray
    command: Command
    projection: Projection
    forward_speed_mps: FloatArray
    density_per_m2: float
    r_a_m: FloatArray
    parked: NDArray[np.bool_]
    done: bool


class SwarmStep:
    """The swarm controller with its state (avoidance radii, parking assignment), one call per control period.

    Parameters
    ----------
    tube
        The tube to fly (:class:`~vtube_planning.onboard.tube.StepTube`): the exact
        :class:`~vtube_planning.geometry.tube.VirtualTube` or the testbed's
        :class:`~vtube_planning.onboard.sampled_tube.SampledTube`.
    params
        The step's numbers.
    n_robots
        Swarm size.
    plan
        The plan to track (forward speed v*(l_i), and r_a by (a3)); None flies *without planning*: constant
        forward speed, constant r_a.
    constant_speed_mps
        The forward speed without a plan.
    parking_slots
        Slots (2, N) beyond the exit for robots that leave the tube; None lets them fly on. A robot leaves for its
        slot once it is as far beyond the exit as the nearest slot: until then it flies the law, along the tube
        (turning for a slot at the exit put the bodies of robots leaving beside a wall over it: 25 robot-steps on
        the trapezoid without initialization). The swarm is done when every robot is *seen* in its slot.
    warm_projection
        Project the robots starting from their previous projection (``tube.project_near``: the same arc lengths
        to about 1e-12 m, certified or else searched globally) instead of searching the whole tube each period
        (``tube.project``). Only when the step projects, i.e. is not given the projection.
    velocity
        The robots' velocity (2, N) before the first command, for the delay compensation
        (``params.compensates``): what they do until the first command arrives; None: at rest.

    With ``params.compensates`` the step acts on where every robot will be once its command arrives, predicted
    from the commands the step gave (:meth:`sent` replaces the last one when the caller sent another); a given
    projection is then ignored, the predicted points are projected.
    """

    def __init__(
        self,
        tube: StepTube,
        params: StepParams,
        n_robots: int,
        *,
        plan: PlanProfile | None = None,
        constant_speed_mps: float | None = None,
        parking_slots: FloatArray | None = None,
        warm_projection: bool = True,
        velocity: FloatArray | None = None,
    ) -> None:
        if plan is None and constant_speed_mps is None:
            msg = 'a swarm step without a plan needs constant_speed_mps, the forward speed to fly.'
            raise ValueError(msg)
        self.tube = tube
        self.params = params
        self.plan = plan
        self.constant_speed_mps = float(constant_speed_mps) if constant_speed_mps is not None else math.nan
        self.parking, self.leave_at_m = None, tube.length_m  # where a robot leaves the tube (``parking_slots``)
        if parking_slots is not None:
            slots = tube.project(parking_slots)
            self.parking = Parking(parking_slots, n_robots, slots.l_m - tube.length_m, slots.y_m)
            self.leave_at_m = max(tube.length_m, float(slots.l_m.min()))
        self.r_a = np.full(n_robots, float(params.r_a_m))
        self.warm_projection = warm_projection
        self._last: Projection | None = None  # the last period's projection, where the warm start begins
        self._velocity = velocity  # the robots' velocity before the first command (the predictor's start)
        self.predictor: CommandPredictor | None = None  # made at the first period, which gives the period
        self._sent: FloatArray | None = None  # the last period's command, told to the predictor at the next one

    def __call__(
        self, points: FloatArray, dt_s: float, projection: Projection | None = None, others: FloatArray | None = None
    ) -> StepResult:
        """The commands for robots at (2, N) ``points``; advances r_a and the parking assignment by ``dt_s``.

        ``others`` (2, N): where the robots hear each other (their last messages); None: at ``points``.
        """
        p = self.params
        points = np.asarray(points, dtype=float)
        if points.shape != (2, self.r_a.size):
            msg = f'points must have shape (2, {self.r_a.size}), one robot per column; got {points.shape}.'
            raise ValueError(msg)
        if np.count_nonzero(np.isfinite(points)) < points.size:  # a count: the cheapest test of a small array
            msg = f'points of robots {np.flatnonzero(~np.isfinite(points).all(axis=0)).tolist()} are not finite.'
            raise ValueError(msg)
        measured = points
        if p.compensates:
            if self.predictor is None:
                delay, lag = p.compensate_delay_steps, p.compensate_lag_s
                self.predictor = CommandPredictor(self.r_a.size, delay, lag, dt_s, self._velocity)
            if self._sent is not None:
                self.predictor.sent(self._sent)
            points, projection = self.predictor.predict(points), None
        if projection is None:
            if self.warm_projection and self._last is not None:
                projection = self.tube.project_near(points, self._last)
            else:
                projection = self.tube.project(points)
        self._last = projection
        l_m = projection.l_m
        exited = l_m > self.leave_at_m  # past the exit: the swarm's passage is over for this robot
        parked = (
            self.parking.take(exited, projection.y_m) if self.parking is not None else np.zeros(l_m.size, dtype=bool)
        )
        members = ~parked if np.count_nonzero(parked) else None  # None: every robot flies the tube
        swarm_l, radii = (l_m[members], self.r_a[members]) if members is not None and members.any() else (l_m, self.r_a)
        density = swarm_density(self.tube, swarm_l, p.r_a_m if p.density_padding == 'initial' else float(radii.mean()))
        l_plan = np.full(l_m.size, swarm_l.mean()) if p.plan_at == 'center' else l_m
        if self.plan is not None:
            forward_speed = self.plan.speed(l_plan)
            if p.stretch_gain_mps:
                rho_center = float(self.plan.density(np.array([swarm_l.mean()]))[0])
                band = (p.v_min_mps, p.v_max_mps)
                forward_speed = stretched_speed(
                    forward_speed, l_m, swarm_l, density, rho_center, p.stretch_gain_mps, band
                )
        else:
            forward_speed = np.full(l_m.size, self.constant_speed_mps)
        r_a = self.r_a
        command = velocity_command(points, r_a, forward_speed, projection, p, members, others)
        velocity = command.velocity
        if self.parking is None:
            done = np.count_nonzero(exited) == exited.size
        else:
            velocity = self.parking.drive(points, parked, velocity, p.v_max_mps)
            done = self.parking.all_in(measured, parked)  # where the robots are seen, not where they are predicted
        if self.plan is not None:
            self.r_a = next_radius(r_a, density, self.plan.density(l_plan), p, dt_s)
        self._sent = velocity
        return StepResult(velocity, command, projection, forward_speed, density, r_a, parked, done)

    def sent(self, velocity: FloatArray) -> None:
        """The caller sent ``velocity`` (2, N) this period instead of the step's own command (a safety filter
        changed it): the delay compensation predicts from what was sent."""
        self._sent = np.array(velocity, dtype=float)
