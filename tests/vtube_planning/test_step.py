"""The swarm step against hand-computed values, docs/theory.md's published numbers and finite differences; the sampled
tube against the exact one; the step as the submission inlines it against the library's."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from vtube_planning import ArcPath, ArcPiece, ParamsError, SwarmParams, VirtualTube, WidthPart, WidthProfile
from vtube_planning.onboard import (
    KDTREE_ABOVE,
    Command,
    PlanProfile,
    SwarmStep,
    avoidance_velocity,
    interaction_gains,
    velocity_command,
)
from vtube_planning.onboard.neighbours import neighbour_pairs
from vtube_planning.onboard.radius import avoidance_radius_rate, feedforward_radius, next_radius
from vtube_planning.onboard.scalar import barrier_gain, saturate, sigma, smooth_saturation
from vtube_planning.params import ControlParams

SWARM = SwarmParams()  # r_s = 0.4, r_a = 0.8, v in [2, 5]
PRACTICAL = ControlParams(law='practical', avoidance_gain=2.0, keeping_gain=3.0)


def command_at(
    positions: np.ndarray, r_a: np.ndarray, forward: np.ndarray, tube: VirtualTube, control: ControlParams
) -> Command:
    """The law at positions with the exact projection."""
    return velocity_command(positions, r_a, forward, tube.project(positions), control.step_params(SWARM))


def wide_tube(half_width_m: float = 10.0) -> VirtualTube:
    return VirtualTube(ArcPath((ArcPiece(50.0),)), WidthProfile(half_width_m, (WidthPart('constant', 50.0),)))


def sigma_published(x: float, d1: float, d2: float) -> float:
    """docs/theory.md §2.3 with its coefficients A, B, C, D."""
    den = (d1 - d2) ** 3
    if x <= d1:
        return 1.0
    if x >= d2:
        return 0.0
    return (-2 * x**3 + 3 * (d1 + d2) * x**2 - 6 * d1 * d2 * x + d2**2 * (3 * d1 - d2)) / den


def barrier_potential(x: float, offset: float, d1: float, d2: float, k: float, eps: float = 1e-6) -> float:
    """V = k sigma / ((1 + eps) x - offset s(x / offset)) written out from docs/theory.md §2.3-2.4."""
    x2 = 1 + eps / math.tan(math.radians(67.5))
    x1 = x2 - eps * math.sin(math.radians(45))
    u = x / offset
    s = u if u <= x1 else (1.0 if u >= x2 else (1 - eps) + math.sqrt(eps**2 - (u - x2) ** 2))
    return k * sigma_published(x, d1, d2) / ((1 + eps) * x - offset * s)


# ---------------------------------------------------------------------- building blocks


def test_sigma_matches_the_published_polynomial_and_its_band_edges() -> None:
    x = np.linspace(0.5, 1.5, 401)
    value, _ = sigma(x, 0.8, 1.2)
    np.testing.assert_allclose(value, [sigma_published(v, 0.8, 1.2) for v in x], atol=1e-12)
    edges, edge_slopes = sigma(np.array([0.8, 1.2]), 0.8, 1.2)
    np.testing.assert_allclose(edges, [1.0, 0.0])
    np.testing.assert_allclose(edge_slopes, [0.0, 0.0])
    h = 1e-6
    inner = x[(x > 0.81) & (x < 1.19)]
    fd = (sigma(inner + h, 0.8, 1.2)[0] - sigma(inner - h, 0.8, 1.2)[0]) / (2 * h)
    np.testing.assert_allclose(sigma(inner, 0.8, 1.2)[1], fd, atol=1e-7)
    assert np.all(np.diff(value) <= 0)  # monotone


@pytest.mark.parametrize('eps', [1e-6, 0.1, 0.3])
def test_smooth_saturation_is_c1_at_both_corners(eps: float) -> None:
    x2 = 1 + eps / math.tan(math.radians(67.5))
    x1 = x2 - eps * math.sin(math.radians(45))
    h = 1e-5 * eps  # small against the arc, which is about eps wide
    value, slope = smooth_saturation(np.array([x1 - h, x1 + h, x2 - h, x2 + h]), eps)
    np.testing.assert_allclose(value, [x1, x1, 1.0, 1.0], atol=2 * h)  # continuous: values differ by the step
    np.testing.assert_allclose(slope[[0, 1]], 1.0, atol=1e-3)
    np.testing.assert_allclose(slope[[2, 3]], 0.0, atol=2e-3)
    x = np.linspace(0.2, 1.6, 200)
    fd = (smooth_saturation(x + 1e-7, eps)[0] - smooth_saturation(x - 1e-7, eps)[0]) / 2e-7
    np.testing.assert_allclose(smooth_saturation(x, eps)[1], fd, atol=1e-5)


def test_barrier_potential_reproduces_theory_values() -> None:
    # docs/theory.md §2.4: r_s = 0.4, r_a = 0.8, k2 = 1, eps = 1e-6
    for x, expected in ((0.81, 99.8), (0.9, 8.4), (1.0, 2.5)):
        assert barrier_potential(x, 0.8, 0.8, 1.2, 1.0) == pytest.approx(expected, rel=0.01)
    assert barrier_potential(0.79, 0.8, 0.8, 1.2, 1.0) == pytest.approx(1.27e6, rel=0.01)
    assert barrier_potential(1.2, 0.8, 0.8, 1.2, 1.0) == 0.0


def test_barrier_gain_is_minus_the_potential_derivative() -> None:
    x = np.linspace(0.82, 1.25, 60)
    h = 1e-7
    fd = np.array(
        [
            -(barrier_potential(v + h, 0.8, 0.8, 1.2, 1.0) - barrier_potential(v - h, 0.8, 0.8, 1.2, 1.0)) / (2 * h)
            for v in x
        ]
    )
    np.testing.assert_allclose(barrier_gain(x, 0.8, 0.8, np.full(x.shape, 1.2), 1.0), fd, rtol=1e-5, atol=1e-6)
    assert np.all(barrier_gain(np.array([1.2, 2.0]), 0.8, 0.8, np.full(2, 1.2), 1.0) == 0.0)
    assert barrier_gain(np.array([0.5]), 0.8, 0.8, np.array([1.2]), 1.0)[0] > 1e6  # inside the safety distance


@pytest.mark.parametrize('law', ['barrier', 'practical'])
def test_one_evaluation_of_the_law_gives_the_bits_of_separate_ones(law: str) -> None:
    """Pairs (offset and d1 = 2 r_s, the avoidance gain) and walls (r_s, the keeping gain) in one call of the law,
    element by element: exactly what each kind gives alone with scalar parameters (the simulator's runs depend on
    these bits); with no pairs or no walls, the other kind alone."""
    params = replace(PRACTICAL, law=law).step_params(SWARM)
    r_s = params.r_s_m
    rng = np.random.default_rng(7)
    dist = rng.uniform(0.5, 1.6, 40)  # inside the safety distance 2 r_s, the band and beyond
    band = r_s + rng.uniform(0.8, 1.2, 40)
    clearance = rng.uniform(-0.1, 1.0, 12)
    r_a = rng.uniform(0.8, 1.2, 12)
    if law == 'barrier':
        pairs = barrier_gain(dist, 2 * r_s, 2 * r_s, band, params.avoidance_gain)
        walls = barrier_gain(clearance, r_s, r_s, r_a, params.keeping_gain)
    else:
        pairs = params.avoidance_gain * sigma(dist, 2 * r_s, band)[0]
        walls = params.keeping_gain * sigma(clearance, r_s, r_a)[0]
    assert np.count_nonzero(pairs) > 10 and np.count_nonzero(walls) > 3  # both kinds push
    together = interaction_gains(dist, band, clearance, r_a, params)
    np.testing.assert_array_equal(together[0], pairs)
    np.testing.assert_array_equal(together[1], walls)
    none = np.empty(0)
    np.testing.assert_array_equal(interaction_gains(dist, band, none, none, params)[0], pairs)
    np.testing.assert_array_equal(interaction_gains(none, none, clearance, r_a, params)[1], walls)


def test_saturate_rescales_radially_into_the_speed_band() -> None:
    u = np.array([[0.5, 3.0, 30.0, 0.0], [0.0, 4.0, 40.0, 0.0]])
    fallback = np.array([[1.0] * 4, [0.0] * 4])
    v = saturate(u, 2.0, 5.0, fallback)
    np.testing.assert_allclose(v.T, [[2.0, 0.0], [3.0, 4.0], [3.0, 4.0], [2.0, 0.0]])
    rng = np.random.default_rng(5)
    u = rng.normal(0.0, 4.0, (2, 30))
    with_zero = np.hstack([u, np.zeros((2, 1))])  # one zero command: the general path for every column
    fallback = np.vstack([np.ones(31), np.zeros(31)])
    np.testing.assert_array_equal(
        saturate(u, 2.0, 5.0, fallback[:, :30]), saturate(with_zero, 2.0, 5.0, fallback)[:, :30]
    )


# ---------------------------------------------------------------------- the law, by hand


def test_two_robots_practical_law_by_hand() -> None:
    tube = wide_tube()
    positions = np.array([[10.0, 11.0], [0.0, 0.0]])  # 1 m apart along the tube, on the centre line
    command = command_at(positions, np.full(2, 0.8), np.full(2, 3.0), tube, PRACTICAL)
    push = 2.0 * 0.5  # k_m sigma(1.0; 0.8, 1.2): the middle of the band
    np.testing.assert_allclose(command.avoidance.T, [[-push, 0.0], [push, 0.0]], atol=1e-12)
    np.testing.assert_allclose(command.tube_keeping, 0.0, atol=1e-12)  # 10 m from both walls
    np.testing.assert_allclose(command.velocity.T, [[3.0 - push, 0.0], [3.0 + push, 0.0]], atol=1e-12)


def test_three_robots_sum_their_pushes_and_use_their_own_radius() -> None:
    tube = wide_tube()
    positions = np.array([[10.0, 11.0, 10.0], [0.0, 0.0, 0.9]])
    r_a = np.array([0.8, 0.8, 0.3 + 0.4])  # the third robot's band ends at r_s + r_a = 1.1 m
    command = command_at(positions, r_a, np.full(3, 3.0), tube, PRACTICAL)
    s_10 = sigma_published(1.0, 0.8, 1.2)
    s_09 = sigma_published(0.9, 0.8, 1.2)
    d = math.hypot(1.0, 0.9)  # robots 2 and 3
    s_23 = sigma_published(d, 0.8, 1.2)  # zero: 1.345 m is beyond the band of robots 1 and 2
    expected_0 = 2.0 * (s_10 * np.array([-1.0, 0.0]) + s_09 * np.array([0.0, -1.0]))
    expected_1 = 2.0 * (s_10 * np.array([1.0, 0.0]) + s_23 * np.array([1.0, -0.9]) / d)
    expected_2 = 2.0 * sigma_published(0.9, 0.8, 1.1) * np.array([0.0, 1.0])  # its own, narrower band
    np.testing.assert_allclose(command.avoidance.T, [expected_0, expected_1, expected_2], atol=1e-12)


def test_tube_keeping_pushes_towards_the_centre_line() -> None:
    tube = wide_tube(2.0)
    positions = np.array([[5.0, 5.0, 5.0], [1.4, -1.4, 0.0]])  # 0.6 m from the left / right wall, centre
    command = command_at(positions, np.full(3, 0.8), np.full(3, 3.0), tube, PRACTICAL)
    push = 3.0 * sigma_published(0.6, 0.4, 0.8)
    np.testing.assert_allclose(command.tube_keeping.T, [[0.0, -push], [0.0, push], [0.0, 0.0]], atol=1e-12)


def test_commands_always_lie_in_the_speed_band() -> None:
    rng = np.random.default_rng(0)
    tube = wide_tube(3.0)
    for law in ('practical', 'barrier'):
        positions = np.vstack([rng.uniform(0, 20, 300), rng.uniform(-3.5, 3.5, 300)])
        command = command_at(
            positions, rng.uniform(0.8, 2.0, 300), rng.uniform(2, 5, 300), tube, ControlParams(law=law)
        )
        speed = np.hypot(*command.velocity)
        assert np.all(speed >= 2.0 - 1e-9) and np.all(speed <= 5.0 + 1e-9)


def test_the_forward_progress_form_never_reverses_and_stays_in_the_band() -> None:
    """Random crowds: forward component >= v_min, speed <= v_max; where the pushes fit the room v* - v_min the
    command is v* t_c plus the pushes unchanged; where the paper's radial sat would send a robot backwards, it does
    not."""
    rng = np.random.default_rng(7)
    tube = wide_tube(3.0)
    forward_law = ControlParams(saturation='forward')
    positions = np.vstack([rng.uniform(0, 20, 300), rng.uniform(-3.5, 3.5, 300)])
    r_a, v_star = rng.uniform(0.8, 2.0, 300), rng.uniform(2, 5, 300)
    command = command_at(positions, r_a, v_star, tube, forward_law)
    tangent = tube.project(positions).tangent
    along = np.einsum('ij,ij->j', command.velocity, tangent)
    assert np.all(along >= 2.0 - 1e-9) and np.all(np.hypot(*command.velocity) <= 5.0 + 1e-9)
    gentle = command_at(
        positions,
        r_a,
        v_star,
        tube,
        ControlParams(law='practical', saturation='forward', avoidance_gain=0.2, keeping_gain=0.2),
    )
    pushes = gentle.avoidance + gentle.tube_keeping
    small = (np.hypot(*pushes) <= v_star - 2.0) & (np.hypot(*(gentle.forward + pushes)) <= 5.0)
    assert small.sum() > 20
    np.testing.assert_allclose(gentle.velocity[:, small], (gentle.forward + pushes)[:, small], atol=1e-12)
    radial = command_at(positions, r_a, v_star, tube, ControlParams())
    backwards = np.einsum('ij,ij->j', radial.velocity, tangent) < 0
    assert backwards.sum() > 5  # the crowd is tight enough for the radial sat to reverse some robots


@pytest.mark.parametrize('n', [KDTREE_ABOVE // 2, 5 * KDTREE_ABOVE])
def test_kd_tree_and_all_pairs_give_the_same_law(n: int) -> None:
    """Below and above the crossover, each path forced: the same pairs and the same avoidance term."""
    rng = np.random.default_rng(n)
    side = np.sqrt(n)  # about one robot per m^2, so robots have neighbours within and beyond their bands
    positions = np.vstack([rng.uniform(0, 2 * side, n), rng.uniform(0, 0.5 * side, n)])
    r_a = rng.uniform(0.8, 1.6, n)
    members = rng.random(n) > 0.1
    for law in ('barrier', 'practical'):
        dense = avoidance_velocity(positions, r_a, ControlParams(law=law, kdtree_above=n).step_params(SWARM), members)
        tree = avoidance_velocity(positions, r_a, ControlParams(law=law, kdtree_above=0).step_params(SWARM), members)
        assert np.count_nonzero(np.hypot(*dense)) > n // 4  # the test sees pushes
        np.testing.assert_allclose(tree, dense, rtol=1e-12, atol=1e-12 * np.abs(dense).max())
    i, j = neighbour_pairs(positions, 1.5)
    every = [(a, b, math.dist(positions[:, a], positions[:, b])) for a in range(n) for b in range(a + 1, n)]
    assert sorted(zip(i.tolist(), j.tolist())) == [(a, b) for a, b, dist in every if dist < 1.5]


def test_the_warm_step_commands_what_the_reference_step_does() -> None:
    """The default step (all pairs or tree by N, warm projection) against the reference (tree, cold) on a curved
    tube, robots moving: the same commands, radii and densities period after period."""
    from vtube_planning import load_scene

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


def test_avoidance_radius_law_only_expands() -> None:
    params = ControlParams(k_ra_m3ps=4.0).step_params(SWARM)
    rate = avoidance_radius_rate(0.3, np.array([0.2, 0.3, 0.5]), params)
    np.testing.assert_allclose(rate, [0.4, 0.0, 0.0])
    np.testing.assert_allclose(feedforward_radius(np.array([0.25]), params), [2.0 - 0.4])  # 1/sqrt(rho) - r_s


def test_avoidance_radius_update_caps_and_feeds_forward() -> None:
    r_a = np.array([0.8, 1.0, 2.3])
    plain = ControlParams(k_ra_m3ps=4.0, r_a_max_m=2.4).step_params(SWARM)
    # rate 4 (0.3 - rho*): 0.4, 0.0, 0.4 m/s over 0.5 s; the third robot stops at the cap
    np.testing.assert_allclose(next_radius(r_a, 0.3, np.array([0.2, 0.5, 0.2]), plain, 0.5), [1.0, 1.0, 2.4])
    fed = ControlParams(k_ra_m3ps=4.0, r_a_max_m=2.4, feedforward=True).step_params(SWARM)
    # rho* = 0.25 -> 1/sqrt(rho*) - r_s = 1.6 m floors the first two; rho* = 0.01 -> 9.6 m, capped at 2.4
    np.testing.assert_allclose(next_radius(r_a, 0.3, np.array([0.25, 0.25, 0.01]), fed, 0.5), [1.6, 1.6, 2.4])


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
        'kdtree_above': 7,
    }
    assert {f.name for f in fields(ControlParams)} == set(changed)
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
