"""One period of the tube experiment on a Robotarium, and the loop around it: the bundled experiment and the
submitted file run this same code (:mod:`submission.builder` inlines it).

Each period:

1. poses -> control points p + d e_theta (:mod:`unicycle_mapping`);
2. the swarm step (:class:`~vtube_planning.onboard.stepper.SwarmStep`) on the control points: the plan's forward term
   (or a constant speed), avoidance, tube keeping, sat, (a3); robots past the exit drive to parking slots;
3. the safety filter (:mod:`robotarium_exp.safety`): the barrier certificate with the arena boundary, and the
   speed band of the robots still flying the tube, in one exact QP; where both cannot hold, safety wins;
4. the speed-constrained map to [v; omega] for the flying robots (forward speed in [v_min, v_max]), the exact
   near-identity map and uniform wheel scaling for the others.

The loop (:func:`fly`) hands the commands to ``set_velocities`` and calls ``step()`` until every robot has parked
or the step limit; the caller records each period as it likes, and :func:`flight_start` where on the Robotarium's
clock the flight (and with it the passage) begins, after the initialization. It needs numpy only and uses the Robotarium
object through ``get_poses``, ``set_velocities`` and ``step``, so any ``rps`` implementation runs it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.flight_data import FlightData, Wheels
from robotarium_exp.rps.utilities.barrier_rows import BarrierSpec
from robotarium_exp.safety import EXIT_KEEP_M, WALL_KEEP_M, SafetyFilter
from unicycle_mapping.mapping import si_to_uni, si_to_uni_constrained, uni_to_si_states
from unicycle_mapping.wheels import scale_to_wheel_limits
from vtube_planning.onboard import Projection, SampledTube, StepResult, SwarmStep

FloatArray = NDArray[np.float64]


class RobotariumLike(Protocol):
    """What a flight uses of a Robotarium object (any ``rps`` generation)."""

    def get_poses(self) -> FloatArray: ...

    def set_velocities(self, ids: NDArray[np.int_], velocities: FloatArray) -> None: ...

    def step(self) -> None: ...


@dataclass(frozen=True)
class Period:
    """One control period: the poses, control points, the swarm step, the filtered velocities, the commands.

    ``flying`` marks the robots still flying the tube (not parked); ``band_held`` is False in a step where the
    safety filter had to drop their speed band (safety won).
    """

    poses: FloatArray
    points_m: FloatArray
    step: StepResult
    safe_mps: FloatArray
    dxu: FloatArray
    flying: NDArray[np.bool_]
    band_held: bool

    @property
    def barrier_correction_mps(self) -> FloatArray:
        """How much the safety filter changed each robot's velocity, (N,)."""
        change = self.safe_mps - self.step.velocity
        correction: FloatArray = np.hypot(change[0], change[1])
        return correction


class Flight:
    """The experiment's controller: control points, swarm step, safety filter, speed-constrained map.

    Parameters
    ----------
    stepper
        The swarm step with its plan, tube and parking slots.
    safety
        The safety filter (barrier rows, the speed band of flying robots, the wheel limits), or None.
    projection_distance_m
        d of the near-identity map.
    wheels
        The drive's limits.
    """

    def __init__(
        self, stepper: SwarmStep, safety: SafetyFilter | None, projection_distance_m: float, wheels: Wheels
    ) -> None:
        self.stepper = stepper
        self.safety = safety
        self.d = float(projection_distance_m)
        self.wheels = wheels

    def __call__(self, poses: FloatArray, dt_s: float) -> Period:
        """The commands for robots at ``poses`` (3, N); advances the swarm's state by ``dt_s``.

        Flying robots whose band held go through the speed-constrained map (v in [v_min, v_max]; the filter's
        rows keep it exact); parked robots, and every robot in a step where safety won, through the exact map;
        then every robot through uniform wheel scaling (the filter's wheel rows hold a wheel at its limit, which the
        scaling keeps a hair below).
        """
        points = uni_to_si_states(poses, self.d)
        step = self.stepper(points, dt_s)
        flying = ~step.parked
        safe, held = step.velocity, True
        if self.safety is not None:
            slope = self.stepper.tube.half_width_slope(step.projection.l_m)
            safe, held = self.safety(step.velocity, poses, points, flying, walls(step.projection, flying, slope))
            self.stepper.sent(safe)  # a delay compensation predicts from what the robots are sent
        dxu = si_to_uni(safe, poses, self.d)
        p = self.stepper.params
        if held and self.safety is not None and flying.any():
            turn = p.v_max_mps * self.safety.lateral_max / self.d  # never binds: the filter bounds |omega| below
            banded, _ = si_to_uni_constrained(
                safe[:, flying], poses[:, flying], self.d, v_min=p.v_min_mps, v_max=p.v_max_mps, a_n=turn
            )
            dxu[:, flying] = banded
        w = self.wheels
        dxu, _ = scale_to_wheel_limits(dxu, w.base_length_m, w.wheel_radius_m, w.max_wheel_speed_radps)
        return Period(poses, points, step, safe, dxu, flying, held)


def walls(
    projection: Projection, flying: NDArray[np.bool_], slope: FloatArray | float = 0.0
) -> tuple[FloatArray, FloatArray]:
    """The safety filter's walls, as the outward direction o (2, N) and the room h (N,) above what the rows keep: for
    a robot flying from the entrance on (past the exit too, on the walls' extension, until it leaves for its slot:
    its control point passes the exit before its body does), its nearer wall (h: the control point's clearance
    lambda(l) - |y| less :data:`~robotarium_exp.safety.WALL_KEEP_M`); for a parked robot, the exit line behind it
    (h: how far beyond the exit less :data:`~robotarium_exp.safety.EXIT_KEEP_M`), so that nobody pushes it back
    beside the tube; NaN (no row) otherwise.

    o is minus h's gradient, so that the row o . u <= gain h is dh/dt >= -gain h: across the tube sign(y) n, and
    where the tube narrows, ``slope`` (d lambda / dl at the feet, 0 by default) times -t / (1 - kappa y): a robot
    flying on along a narrowing loses room even when it does not move sideways (the trapezoid's 48 degree walls
    take 1.1 m of room per metre flown). Without that term the rows let a crowd of twenty robots put bodies on the
    walls at the narrowing's end under the testbed's delay (``docs/howto/submitting.md``)."""
    l_m, length = projection.l_m, projection.length_m
    inside = flying & (l_m >= 0.0)  # past the exit too, until it leaves: its body may still be beside the walls
    bend = np.maximum(1.0 - projection.curvature_per_m * projection.y_m, 0.1)  # dl = t . dp / (1 - kappa y)
    along = np.asarray(slope) / bend
    across = np.sign(projection.y_m) * projection.normal - along * projection.tangent
    outward = np.where(flying, across, -projection.tangent)
    wall = projection.half_width_m - np.abs(projection.y_m) - WALL_KEEP_M
    room = np.where(inside, wall, np.where(flying, np.nan, l_m - length - EXIT_KEEP_M))
    return outward, room


def build_flight(data: FlightData) -> Flight:
    """The flight described by ``data`` (:func:`robotarium_exp.experiment.flight_data`, a submission's ``DATA``)."""
    tube = SampledTube(data.tube.l_m, data.tube.xy_m, data.tube.half_width_m, data.tube.area_m2)
    params = data.step
    stepper = SwarmStep(
        tube,
        params,
        data.n_robots,
        plan=data.plan,
        constant_speed_mps=data.constant_speed_mps,
        parking_slots=data.parking_slots,
    )
    wheels = data.wheels
    d = data.projection_distance_m
    safety = None
    if data.safety is not None:
        barrier = BarrierSpec(
            data.safety.safety_radius_m, data.safety.barrier_gain, params.v_max_mps, data.safety.arena_m, False
        )
        safety = SafetyFilter(
            barrier, params.v_min_mps, params.v_max_mps, d, wheels.base_length_m, wheels.rim_speed_mps
        )
    return Flight(stepper, safety, d, wheels)


def fly(
    robotarium: RobotariumLike, flight: Flight, dt_s: float, max_steps: int, record: Callable[[int, Period], None]
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


def robotarium_steps(robotarium: object) -> int:
    """Steps the Robotarium has taken so far, initialization included (``iterations``: ours; ``_iteration``,
    ``_iterations``: V2's and classic's); 0 when it does not say."""
    for name in ('iterations', '_iteration', '_iterations'):
        steps = getattr(robotarium, name, None)
        if steps:
            return int(steps)
    return 0


def flight_start(robotarium: object, dt_s: float) -> dict[str, float | int]:
    """Where the flight begins, for a log's description: the Robotarium's steps before it (the initialization, when
    one ran), their time, and the log's time ``t_s`` at that moment (0: a flight's log starts with its first period).

    A returned log that records its start is timed as the experiment times it (:mod:`robotarium_exp.analysis.passage`),
    though every robot starts inside the tube.
    """
    steps = robotarium_steps(robotarium)
    return {'iteration': steps, 'robotarium_time_s': round(steps * dt_s, 6), 't_s': 0.0}
