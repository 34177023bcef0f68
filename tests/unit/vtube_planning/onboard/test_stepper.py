"""The swarm step: the warm step against the reference step, bad input, every control option, where the plan is
read and how the density is padded."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from vtube_planning.errors import ParamsError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.onboard.profile import PlanProfile
from vtube_planning.onboard.stepper import SwarmStep
from vtube_planning.params import ControlParams, SwarmParams

SWARM = SwarmParams()  # r_s = 0.4, r_a = 0.8, v in [2, 5]
PRACTICAL = ControlParams(law='practical', avoidance_gain=2.0, keeping_gain=3.0)


def wide_tube(half_width_m: float = 10.0) -> VirtualTube:
    return VirtualTube(ArcPath((ArcPiece(50.0),)), WidthProfile(half_width_m, (WidthPart('constant', 50.0),)))


def test_the_warm_step_commands_what_the_reference_step_does() -> None:
    """The default step (all pairs or tree by N, warm projection) against the reference (tree, cold) on a curved
    tube, robots moving: the same commands, radii and densities period after period."""
    from vtube_planning.geometry.scene import load_scene

    scene = load_scene('D')
    tube, n = scene.tube, 40
    rng = np.random.default_rng(3)
    l_m = rng.uniform(5.0, 15.0, n)
    points = (tube.center_at(l_m) + rng.uniform(-1.5, 1.5, n)[:, None] * tube.normal(l_m)).T
    params = ControlParams().step_params(SWARM)
    plan = PlanProfile(np.array([0.0, tube.length_m]), np.array([0.4, 0.3]), np.array([0.3, 0.5]))
    now = SwarmStep(tube, params, n, plan=plan)
    before = SwarmStep(tube, replace(params, kdtree_above=0), n, plan=plan, warm_projection=False)
    for _ in range(10):
        a, b = now(points, 0.05), before(points, 0.05)
        np.testing.assert_allclose(a.projection.l_m, b.projection.l_m, rtol=0, atol=1e-9)
        np.testing.assert_allclose(a.velocity, b.velocity, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(a.r_a_m, b.r_a_m, rtol=0, atol=1e-12)
        assert a.density_per_m2 == pytest.approx(b.density_per_m2, rel=1e-12)
        points = points + 0.05 * a.velocity


def test_bad_controller_input_raises() -> None:
    step = SwarmStep(wide_tube(), PRACTICAL.step_params(SWARM), 2, constant_speed_mps=3.0)
    with pytest.raises(ValueError, match=r'points of robots \[1\] are not finite'):
        step(np.array([[0.0, np.nan], [0.0, 1.0]]), 0.02)
    with pytest.raises(ValueError, match=r'points must have shape \(2, 2\), one robot per column; got \(2, 0\)'):
        step(np.zeros((2, 0)), 0.02)
    with pytest.raises(ParamsError, match="control law must be one of \\('practical', 'barrier'\\)"):
        ControlParams(law='magic')
    with pytest.raises(ParamsError, match='r_a_max_m .* below the initial avoidance radius'):
        ControlParams(r_a_max_m=0.5).radius_cap(SWARM)
    with pytest.raises(ParamsError, match='needs r_a_m > r_s_m'):
        ControlParams().step_params(SwarmParams(r_s_m=0.4, r_a_m=0.4))
    with pytest.raises(ParamsError, match='compensate_delay_steps must be a finite number >= 0'):
        ControlParams(compensate_delay_steps=-1.0)
    with pytest.raises(ParamsError, match='compensate_lag_s must be a finite number >= 0'):
        ControlParams(compensate_lag_s=float('nan'))
    with pytest.raises(ParamsError, match='stretch_gain_mps must be a finite number >= 0'):
        ControlParams(stretch_gain_mps=-0.1)


def test_every_control_option_reaches_the_step() -> None:
    """What the step is given is all the submission carries: a control option missing here would be dropped."""
    from dataclasses import fields, replace

    base = ControlParams(r_a_max_m=2.0)
    changed = {
        'avoidance_gain': 2.0,
        'keeping_gain': 3.0,
        'k_ra_m3ps': 4.0,
        'r_a_max_m': 2.5,
        'feedforward': True,
        'law': 'practical',
        'saturation': 'forward',
        'density_padding': 'current',
        'plan_at': 'center',
        'stretch_gain_mps': 0.05,
        'kdtree_above': 7,
        'compensate_delay_steps': 2.0,
        'compensate_lag_s': 0.1,
    }
    # the foresight is the simulator's layer over the step, for robots held to (2)-(4): no submission carries it
    assert {f.name for f in fields(ControlParams)} == {*changed, 'foresight_s'}
    assert replace(base, foresight_s=3.0).step_params(SWARM) == base.step_params(SWARM)
    for name, value in changed.items():
        assert replace(base, **{name: value}).step_params(SWARM) != base.step_params(SWARM), name


def test_the_plan_read_at_the_swarm_centre_is_the_same_for_every_robot() -> None:
    """plan_at='center': one forward speed for all (the plan at the mean arc length); 'robot': each its own."""

    tube = wide_tube()
    ends = np.array([0.0, 50.0])
    plan = PlanProfile(ends, 1.0 / np.array([2.0, 5.0]), np.array([0.3, 0.3]))  # speeds up along the tube
    positions = np.array([[10.0, 20.0, 30.0], [0.0, 3.0, -3.0]])  # far apart: no avoidance, no wall
    speeds = {}
    for where in ('robot', 'center'):
        step = SwarmStep(tube, ControlParams(plan_at=where).step_params(SWARM), 3, plan=plan)
        speeds[where] = step(positions, 0.02).forward_speed_mps
    np.testing.assert_allclose(speeds['robot'], plan.speed(positions[0]))
    np.testing.assert_allclose(speeds['center'], np.full(3, float(plan.speed(20.0))))


def test_a_swarm_denser_than_its_plan_spreads_its_speeds_along_the_tube() -> None:
    """The plan at the centre, stretched (`vtube_planning.onboard.stretch`): three robots 4 m apart on a straight
    tube 20 m wide measure 3 / (20 (8 + 1.6)) robots/m^2; against a plan of half that (e = 1, clipped) the front robot
    goes g faster and the rear one g slower than v*(l_c), the centre one v*(l_c); gain 0 is the law alone."""
    tube = wide_tube()
    measured = 3 / (20 * (8.0 + 2 * 0.8))
    plan = PlanProfile(np.array([0.0, 50.0]), np.full(2, 1.0 / 3.0), np.full(2, 0.5 * measured))
    positions = np.array([[10.0, 14.0, 18.0], [0.0, 3.0, -3.0]])
    speeds = {}
    for gain in (0.0, 0.5):
        params = ControlParams(plan_at='center', stretch_gain_mps=gain).step_params(SWARM)
        speeds[gain] = SwarmStep(tube, params, 3, plan=plan)(positions, 0.02).forward_speed_mps
    np.testing.assert_allclose(speeds[0.0], [3.0, 3.0, 3.0])
    np.testing.assert_allclose(speeds[0.5], [2.5, 3.0, 3.5])


def test_the_density_footprint_is_padded_by_the_initial_or_the_current_radius() -> None:
    """A straight tube of half-width 10 m: the area between l_a and l_b is 20 (l_b - l_a) m^2."""

    tube = wide_tube()
    plan = PlanProfile(np.array([0.0, 50.0]), np.full(2, 1.0 / 3.0), np.full(2, 1e-3))  # sparse plan: r_a grows
    positions = np.array([[10.0, 14.0, 18.0], [0.0, 3.0, -3.0]])
    for padding in ('initial', 'current'):
        step = SwarmStep(tube, ControlParams(density_padding=padding).step_params(SWARM), 3, plan=plan)
        first = step(positions, 0.5)
        assert first.density_per_m2 == pytest.approx(3 / (20 * (8.0 + 2 * 0.8)))  # both: r_a still initial
        step.r_a = np.array([1.0, 1.2, 1.4])  # (a3) has grown the radii
        pad = 0.8 if padding == 'initial' else 1.2
        assert step(positions, 0.5).density_per_m2 == pytest.approx(3 / (20 * (8.0 + 2 * pad)))


def test_a_robot_leaves_for_its_slot_only_as_far_beyond_the_exit_as_the_nearest_slot() -> None:
    """Slots 0.3 and 0.6 m beyond a 50 m tube's exit: a robot 0.1 m past the exit still flies the tube (the law's
    command, a member of the swarm); 0.35 m past, it is parked and heads for its slot (the first: robot order)."""
    slots = np.array([[50.6, 50.3], [0.0, 0.0]])
    step = SwarmStep(wide_tube(), PRACTICAL.step_params(SWARM), 2, constant_speed_mps=3.0, parking_slots=slots)
    behind = step(np.array([[50.1, 40.0], [2.0, 0.0]]), 0.02)
    assert behind.parked.tolist() == [False, False]
    np.testing.assert_allclose(behind.velocity[:, 0], behind.command.velocity[:, 0])
    beyond = step(np.array([[50.35, 40.0], [2.0, 0.0]]), 0.02)
    assert beyond.parked.tolist() == [True, False]
    to_slot = slots[:, 0] - np.array([50.35, 2.0])
    np.testing.assert_allclose(beyond.velocity[:, 0], to_slot * min(1.0, SWARM.v_max_mps / np.hypot(*to_slot)))


def test_with_a_delay_to_compensate_the_robots_seen_in_their_slots_are_done() -> None:
    """Parking steers the predicted control points, but "done" is where the robots are seen: robots standing in
    their slots while a fast command is still on its way (one period of three in flight: predicted 0.2 m on) are
    done; robots 0.05 m beyond their slots, predicted back in them, are not."""
    slots = np.array([[50.6, 50.3], [0.0, 0.0]])
    params = replace(PRACTICAL, compensate_delay_steps=3.0).step_params(SWARM)
    at_slots = slots.copy()
    step = SwarmStep(wide_tube(), params, 2, constant_speed_mps=3.0, parking_slots=slots)
    step(at_slots, 0.1)
    step.sent(np.array([[2.0, 2.0], [0.0, 0.0]]))  # 2 m/s in x for one period of 0.1 s: 0.2 m ahead
    seen_in = step(at_slots, 0.1)
    assert seen_in.parked.all() and seen_in.done
    np.testing.assert_allclose(seen_in.velocity, [[-0.2, -0.2], [0.0, 0.0]], atol=1e-12)  # back to the slots
    beyond = SwarmStep(wide_tube(), params, 2, constant_speed_mps=3.0, parking_slots=slots)
    beyond(slots + [[0.05], [0.0]], 0.1)
    beyond.sent(np.array([[-0.5, -0.5], [0.0, 0.0]]))  # 0.05 m back in one period: predicted at the slots
    predicted_in = beyond(slots + [[0.05], [0.0]], 0.1)
    assert predicted_in.parked.all() and not predicted_in.done
    np.testing.assert_allclose(predicted_in.velocity, 0.0, atol=1e-12)
