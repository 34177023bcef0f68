"""The robot model of the paper, (1)-(4): how a speed-constrained robot's velocity follows a command.

A robot flies p' = v with v_min <= |v| <= v_max (2), its speed changes by at most a_v per second (3) and its
centripetal acceleration |v| |theta'| is at most a_n (4). Over a period dt a robot told to fly at a target speed
and heading moves its speed towards the target by at most a_v dt and turns its heading towards the target's by at
most a_n dt / |v| (the new speed). `respond` is that rule on speeds and headings; the simulator's physics
(`limit_acceleration`) and the foresight's predictions (`vtube_planning.swarm.foresight`) both use it, so the
prediction is the physics. `dynamics_violations` counts the commands a log holds that no robot of the model
could fly from its velocity of that period.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from vtube_planning.params import SwarmParams

FloatArray = NDArray[np.float64]

DYNAMICS_TOLERANCE = 1e-9
"""Speeds (m/s) and speed changes (m/s per period) may exceed the model's bounds by this much before they count."""


def respond(
    speed: FloatArray,
    heading: FloatArray,
    target_speed: FloatArray,
    target_heading: FloatArray,
    a_v: float,
    a_n: float,
    dt_s: float,
) -> tuple[FloatArray, FloatArray]:
    """Speed and heading (rad) after one period ``dt_s`` of following a target speed and heading under (3), (4);
    all arrays broadcast."""
    new_speed = speed + np.clip(target_speed - speed, -a_v * dt_s, a_v * dt_s)
    turn = np.angle(np.exp(1j * (target_heading - heading)))
    max_turn = a_n * dt_s / np.maximum(new_speed, 1e-12)
    return new_speed, heading + np.clip(turn, -max_turn, max_turn)


def limit_acceleration(velocity: FloatArray, command: FloatArray, a_v: float, a_n: float, dt_s: float) -> FloatArray:
    """The velocity (2, N) after one period of following ``command`` (2, N) with |d|v|/dt| <= a_v and
    |v| |dtheta/dt| <= a_n."""
    speed, heading = respond(
        np.hypot(velocity[0], velocity[1]),
        np.arctan2(velocity[1], velocity[0]),
        np.hypot(command[0], command[1]),
        np.arctan2(command[1], command[0]),
        a_v,
        a_n,
        dt_s,
    )
    velocity_after: FloatArray = speed * np.vstack([np.cos(heading), np.sin(heading)])
    return velocity_after


def dynamics_violations(velocities_mps: FloatArray, commands_mps: FloatArray, swarm: SwarmParams, dt_s: float) -> int:
    """Robot-periods whose command (T, 2, N) leaves the model (2)-(4) of ``swarm`` from that period's velocity
    (T, 2, N): a speed outside [v_min, v_max], a speed change above a_v dt, or a turn with |command| |dtheta| above
    a_n dt. NaN entries (no robot) count as neither."""
    a_v, a_n = swarm.a_v_mps2, swarm.a_n_mps2
    speed = np.hypot(velocities_mps[:, 0], velocities_mps[:, 1])
    target = np.hypot(commands_mps[:, 0], commands_mps[:, 1])
    cross = velocities_mps[:, 0] * commands_mps[:, 1] - velocities_mps[:, 1] * commands_mps[:, 0]
    dot = np.einsum('tin,tin->tn', velocities_mps, commands_mps)
    turn = np.abs(np.arctan2(cross, dot))
    v_min, v_max = swarm.v_min_mps, swarm.v_max_mps
    tol = DYNAMICS_TOLERANCE
    with np.errstate(invalid='ignore'):
        broken = (target < v_min - tol) | (target > v_max + tol) | (np.abs(target - speed) > a_v * dt_s + tol)
        broken |= target * turn > a_n * dt_s * (1.0 + 1e-9) + tol
    return int(np.count_nonzero(broken))
