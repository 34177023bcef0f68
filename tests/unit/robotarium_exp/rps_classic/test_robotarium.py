"""The classic ``rps`` generation (``robotarium_exp.rps_classic``): constants, messages, report, laws, the alias.

The expected texts are the official classic simulator's output (PyPI ``robotarium_python_simulator`` 0.0.0, run
under numpy 1.26); the laws are checked against hand computations, robot by robot, on random states.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from robotarium_exp.rps.errors import RobotariumError
from robotarium_exp.rps.utilities import controllers as v2_controllers
from robotarium_exp.rps.utilities import transformations as v2_transformations
from robotarium_exp.rps_classic import robotarium_abc
from robotarium_exp.rps_classic.robotarium import Robotarium
from robotarium_exp.rps_classic.utilities import barrier_certificates as certificates
from robotarium_exp.rps_classic.utilities import controllers, graph, misc, transformations
from robotarium_exp.rps_classic.utilities.barrier_certificates2 import create_robust_barriers

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(autouse=True)
def fresh_counters():
    """Classic shares its counters across instances; each test starts from none and leaves none behind."""
    robotarium_abc.SHARED_ERRORS.clear()
    yield
    robotarium_abc.SHARED_ERRORS.clear()


@pytest.fixture
def states() -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(7)
    x = np.vstack([rng.uniform(-1, 1, (2, 9)), rng.uniform(-np.pi, np.pi, 9)])
    goals = np.vstack([rng.uniform(-1, 1, (2, 9)), rng.uniform(-np.pi, np.pi, 9)])
    return x, goals


def headless(ic: np.ndarray) -> Robotarium:
    return Robotarium(number_of_robots=ic.shape[1], show_figure=False, sim_in_real_time=False, initial_conditions=ic)


# ---------------------------------------------------------------------- the simulator


def test_classic_constants_are_instance_attributes() -> None:
    ic = np.zeros((3, 2))
    ic[0, 1] = 0.5
    r = headless(ic)
    assert r.time_step == 0.033 and r.boundaries == [-1.6, -1, 3.2, 2]
    assert (r.robot_diameter, r.wheel_radius, r.base_length, r.max_linear_velocity) == (0.11, 0.016, 0.105, 0.2)
    assert r.max_wheel_velocity == pytest.approx(12.5) and r.robot_radius == pytest.approx(0.055)
    assert r.max_angular_velocity == pytest.approx(2 * 0.2 / 0.11)
    assert r.get_poses() is ic  # the caller's array itself, updated in place
    assert not hasattr(r, 'TIME_STEP') and not hasattr(r, 'debug')


def test_report_text_and_counts_as_classic_prints_them(capsys) -> None:
    # three robots: 0 and 1 closer than 0.11 m, 2 outside the arena and (first 5 steps) over the wheel limit
    r = headless(np.array([[0.0, 0.05, 1.7], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]))
    for k in range(40):
        r.get_poses()
        r.set_velocities(np.arange(3), np.array([[0.0, 0.0, 0.2], [0.0, 0.0, 3.0 if k < 5 else 0.0]]))
        r.step()
    r.call_at_scripts_end()
    assert capsys.readouterr().out == (
        '##### DEBUG OUTPUT #####\n'
        'Your simulation will take approximately 2 real seconds when deployed on the Robotarium. \n\n'
        '\t Simulation had 40 iteration(s) robots were outside the boundaries.\n\n'
        '\t Simulation had 40 iteration(s) where robots collided.\n\n'
        '\t Simulation had 5 iteration(s) where the actuator limits were exceeded.\n'
    )
    second = headless(np.zeros((3, 1)))  # classic's counters are shared: the first run's counts carry over
    second.get_poses()
    second.step()
    second.call_at_scripts_end()
    out = capsys.readouterr().out
    assert 'approximately 1 real seconds' in out and 'had 40 iteration(s) robots were outside' in out


def test_clean_report(capsys) -> None:
    r = headless(np.zeros((3, 1)))
    r.get_poses()
    r.step()
    r.call_at_scripts_end()
    assert capsys.readouterr().out.endswith('No errors in your simulation! Acceptance of your experiment is likely!\n')


def test_set_velocities_clips_v_and_omega_in_place_and_never_the_wheels() -> None:
    r = headless(np.zeros((3, 1)))
    r.get_poses()
    command = np.array([[0.5], [2.0]])  # wheels (1.0 -/+ 0.21) / 0.032: 24.7 and 37.8 rad/s, left unclipped
    r.set_velocities(np.arange(1), command)
    assert command[0, 0] == 0.2 and command[1, 0] == 2.0  # the caller's array
    r.step()
    np.testing.assert_allclose(r.get_poses()[:, 0], [0.033 * 0.2, 0.0, 0.033 * 2.0], atol=1e-15)
    assert robotarium_abc.SHARED_ERRORS['actuator'] == 1


@pytest.mark.parametrize(
    ('kwargs', 'message'),
    [
        (
            {'number_of_robots': 2.0},
            (
                'The number of robots used argument (number_of_robots) provided to create the Robotarium object must be '
                "an integer type. Recieved type 'float'."
            ),
        ),
        (
            {'number_of_robots': 51},
            (
                'Requested 51 robots to be used when creating the Robotarium object. The deployed number of robots must '
                'be between 0 and 50.'
            ),
        ),
        (
            {'number_of_robots': 2, 'initial_conditions': np.zeros((2, 2))},
            (
                'Initial conditions provided when creating the Robotarium object must of size 3xN, where N is the number '
                'of robots used. Expected a 3 x 2 array but recieved a 2 x 2 array.'
            ),
        ),
        (
            {'number_of_robots': 2, 'initial_conditions': [1]},
            (
                'The initial conditions array argument (initial_conditions) provided to create the Robotarium object '
                "must be a numpy ndarray. Recieved type 'list'."
            ),
        ),
        (
            {'number_of_robots': 2, 'show_figure': 1},
            (
                'The display figure window argument (show_figure) provided to create the Robotarium object must be '
                "boolean type. Recieved type 'int'."
            ),
        ),
        (
            {'number_of_robots': 2, 'show_figure': False, 'sim_in_real_time': 1},
            (
                'The simulation running at 0.033s per loop (sim_real_time) provided to create the Robotarium object '
                "must be boolean type. Recieved type 'bool'."
            ),
        ),
        ({}, 'Requested -1 robots'),
    ],
)
def test_constructor_assertions_have_classic_texts(kwargs: dict, message: str) -> None:
    with pytest.raises(AssertionError) as caught:
        Robotarium(**kwargs)
    assert isinstance(caught.value, RobotariumError) and str(caught.value).startswith(message)


def test_call_order_messages() -> None:
    r = headless(np.zeros((3, 1)))
    with pytest.raises(RobotariumError, match=r'^Make sure to call get_poses before calling step\(\) again\.$'):
        r.step()
    r.get_poses()
    with pytest.raises(RobotariumError, match=r'^Can only call get_poses\(\) once per call of step\(\)\.$'):
        r.get_poses()


def test_random_initial_conditions_are_classic_grid_cells() -> None:
    np.random.seed(11)
    poses = misc.generate_initial_conditions(6, spacing=0.5, width=2.5, height=1.5)
    np.random.seed(11)
    cells = np.random.choice(5 * 3, 6, replace=False) + 1  # 5 columns x 3 rows, cells counted from 1
    expected = [[c // 3 * 0.5 - 1.25, c % 3 * 0.5 - 0.75, np.random.rand() * 2 * np.pi - np.pi] for c in cells]
    np.testing.assert_allclose(poses, np.array(expected).T, atol=1e-15)


def test_misc_hands_plt_to_star_imports() -> None:
    namespace: dict = {}
    exec('from robotarium_exp.rps_classic.utilities.misc import *', namespace)  # noqa: S102 - the point of the test
    assert namespace['plt'].__name__ == 'matplotlib.pyplot' and callable(namespace['at_pose'])


# ---------------------------------------------------------------------- controllers and transformations


def test_si_position_controller_gain_one_not_v2s_point_eight(states) -> None:
    x, goals = states
    goals = x[:2] + 0.05 * (goals[:2] - x[:2])  # small errors: below the magnitude limit
    np.testing.assert_allclose(controllers.create_si_position_controller()(x[:2], goals), goals - x[:2], atol=1e-15)
    np.testing.assert_allclose(
        v2_controllers.create_si_position_controller()(x[:2], goals), 0.8 * (goals - x[:2]), atol=1e-15
    )
    far = controllers.create_si_position_controller()(x[:2], x[:2] + 10.0)
    np.testing.assert_allclose(np.hypot(*far), 0.15)


def test_clf_unicycle_position_controller_by_hand(states) -> None:
    x, goals = states
    dxu = controllers.create_clf_unicycle_position_controller(linear_velocity_gain=0.7, angular_velocity_gain=2.5)(
        x, goals[:2]
    )
    for i in range(x.shape[1]):
        dx, dy = goals[0, i] - x[0, i], goals[1, i] - x[1, i]
        d, bearing = np.hypot(dx, dy), np.arctan2(dy, dx)
        assert dxu[0, i] == pytest.approx(0.7 * d * np.cos(bearing - x[2, i]), abs=1e-14)
        assert dxu[1, i] == pytest.approx(2.5 * d * np.sin(bearing - x[2, i]), abs=1e-14)


def test_clf_unicycle_pose_controller_by_hand(states) -> None:
    x, goals = states
    dxu = controllers.create_clf_unicycle_pose_controller()(x, goals)
    for i in range(x.shape[1]):
        c, s = np.cos(goals[2, i]), np.sin(goals[2, i])
        ex, ey = np.array([[c, s], [-s, c]]) @ (goals[:2, i] - x[:2, i])
        theta = np.arctan2(ey, ex)
        alpha = np.angle(np.exp(1j * (theta - x[2, i] + goals[2, i])))
        assert dxu[0, i] == pytest.approx(np.hypot(ex, ey) * np.cos(alpha), abs=1e-14)
        turn = 2.7 * alpha + np.cos(alpha) * np.sin(alpha) / alpha * (alpha + theta)
        assert dxu[1, i] == pytest.approx(turn, abs=1e-12)


def test_hybrid_pose_controller_by_hand(states) -> None:
    x, goals = states
    goals[:2, :3] = x[:2, :3] + 0.01  # three robots close enough to turn (one also aligned: it stops)
    goals[2, 2] = x[2, 2] + 0.01
    dxu = controllers.create_hybrid_unicycle_pose_controller()(x, goals)
    for i in range(x.shape[1]):
        error = goals[:2, i] - x[:2, i]
        d = np.hypot(*error)
        turn = np.angle(np.exp(1j * (goals[2, i] - x[2, i])))
        if d > 0.03:
            u = error * min(1.0, 0.15 / d)
            along = np.cos(x[2, i]) * u[0] + np.sin(x[2, i]) * u[1]
            across = -np.sin(x[2, i]) * u[0] + np.cos(x[2, i]) * u[1]
            expected = [along, np.pi * np.arctan2(across, along) / (np.pi / 2)]
        elif abs(turn) > 0.05:
            expected = [0.0, 2 * turn]
        else:
            expected = [0.0, 0.0]
        np.testing.assert_allclose(dxu[:, i], expected, atol=1e-14)
    assert np.all(dxu[:, 2] == 0) and np.all(dxu[0, :2] == 0)


def test_si_to_uni_dynamics_gain_enters_the_turn_rate(states) -> None:
    x, goals = states
    dxi = goals[:2]
    dxu = transformations.create_si_to_uni_dynamics(linear_velocity_gain=0.5, angular_velocity_limit=2.0)(dxi, x)
    along = np.cos(x[2]) * dxi[0] + np.sin(x[2]) * dxi[1]
    across = -np.sin(x[2]) * dxi[0] + np.cos(x[2]) * dxi[1]
    np.testing.assert_allclose(dxu, [0.5 * along, 2.0 * np.arctan2(across, 0.5 * along) / (np.pi / 2)], atol=1e-14)
    v2 = v2_transformations.create_si_to_uni_dynamics(0.5, 2.0)(dxi, x)
    assert not np.allclose(v2[1], dxu[1])  # V2 turns by atan2(across, along)


def test_backwards_motion_is_the_forward_law_in_classic(states) -> None:
    x, goals = states
    classic = transformations.create_si_to_uni_dynamics_with_backwards_motion()(goals[:2], x)
    np.testing.assert_array_equal(classic, transformations.create_si_to_uni_dynamics()(goals[:2], x))
    behind = np.cos(x[2]) * goals[0] + np.sin(x[2]) * goals[1] < 0
    assert behind.any() and np.all(classic[0, behind] < 0)
    v2 = v2_transformations.create_si_to_uni_dynamics_with_backwards_motion()(goals[:2], x)
    assert not np.allclose(v2[1, behind], classic[1, behind])  # V2 turns the back of the robot to the command


def test_si_to_uni_mapping_clips_omega(states) -> None:
    x, goals = states
    dxi = goals[:2]
    si_to_uni, uni_to_si_states = transformations.create_si_to_uni_mapping(projection_distance=0.05)
    c, s = np.cos(x[2]), np.sin(x[2])
    omega = (-s * dxi[0] + c * dxi[1]) / 0.05
    assert np.any(np.abs(omega) > np.pi)  # the pin means something: some commands are clipped
    np.testing.assert_allclose(si_to_uni(dxi, x), [c * dxi[0] + s * dxi[1], np.clip(omega, -np.pi, np.pi)])
    np.testing.assert_allclose(v2_transformations.create_si_to_uni_mapping()[0](dxi, x)[1], omega)  # V2: no clip
    np.testing.assert_allclose(uni_to_si_states(x), x[:2] + 0.05 * np.vstack([c, s]))
    dxu = goals[:2]
    back = transformations.create_uni_to_si_dynamics(projection_distance=0.05)(dxu, x)
    np.testing.assert_allclose(back, [c * dxu[0] - 0.05 * s * dxu[1], s * dxu[0] + 0.05 * c * dxu[1]])


def test_graph_names_and_topological_neighbours() -> None:
    lap = graph.cycle_GL(5)
    np.testing.assert_array_equal(lap.sum(axis=1), 0)
    assert lap[0, 4] == lap[4, 0] == lap[2, 3] == -1 and np.all(np.diag(lap) == 2)
    np.testing.assert_array_equal(graph.topological_neighbors(lap, 0), [1, 4])
    assert lap[0, 0] == 0  # classic edits the caller's Laplacian as it reads the row


# ---------------------------------------------------------------------- barrier certificates


@pytest.mark.parametrize(
    'name',
    [n for n in certificates.__all__ if 'differential_drive' not in n],  # those solve exactly (quadprog)
)
def test_cvxopt_certificates_answer_as_the_official_classic_ones(name: str) -> None:
    """With the testbed's solver (the default), classic's cvxopt certificates give the PyPI simulator's answers."""
    official = pytest.importorskip('rps.utilities.barrier_certificates')  # PyPI robotarium-python-simulator
    theirs, ours = getattr(official, name)(), getattr(certificates, name)()
    unicycle = 'unicycle' in name
    rng = np.random.default_rng(6)
    worst = 0.0
    for _ in range(20):
        n = int(rng.integers(2, 10))
        x = np.vstack([rng.uniform(-0.6, 0.6, (2, n)), rng.uniform(-np.pi, np.pi, n)])
        if not unicycle:
            x = x[:2]
        u = np.vstack([rng.uniform(-0.2, 0.2, n), rng.uniform(-3, 3, n)]) if unicycle else rng.normal(0, 0.15, (2, n))
        worst = max(worst, float(np.abs(np.asarray(theirs(u.copy(), x.copy())) - ours(u, x)).max()))
    assert worst <= 1e-9


@pytest.mark.usefixtures('exact_qp')
def test_certificate2_uses_the_unsafe_gain_inside_the_radius() -> None:
    x = np.array([[0.0, 0.1], [0.0, 0.0]])  # 0.1 m apart, inside 0.17 m: h < 0
    request = np.array([[0.2, 0.0], [0.0, 0.0]])  # robot 0 drives into robot 1
    safe = certificates.create_single_integrator_barrier_certificate2(barrier_gain=100, unsafe_barrier_gain=1e3)(
        request, x
    )
    row = np.array([0.2, 0.0, -0.2, 0.0])  # -2 (x_0 - x_1) . (u_0 - u_1) <= gain h^3
    bound = 1e3 * (0.1**2 - 0.17**2) ** 3
    u_hat = request.reshape(-1, order='F')
    expected = u_hat - max(0.0, row @ u_hat - bound) / (row @ row) * row  # projection onto one half-space
    np.testing.assert_allclose(safe.reshape(-1, order='F'), expected, atol=1e-9)
    plain = certificates.create_single_integrator_barrier_certificate(barrier_gain=100)(request, x)
    assert not np.allclose(plain, safe)


@pytest.mark.usefixtures('exact_qp')
def test_unicycle_certificate_maps_back_with_classic_clip() -> None:
    x = np.array([[0.0, 1.0], [0.0, 0.0], [0.0, np.pi / 2]])  # far apart: the certificate is inactive
    dxu = np.array([[0.05, 0.1], [3.4, -1.0]])  # at the points: speeds 0.177 and 0.112, under the limit
    out = certificates.create_unicycle_barrier_certificate()(dxu, x)
    np.testing.assert_allclose(out, [[0.05, 0.1], [np.pi, -1.0]], atol=1e-12)


def test_robust_certificate_keeps_its_constraints() -> None:
    rng = np.random.default_rng(3)
    x = np.vstack([rng.uniform(-0.4, 0.4, (2, 6)), rng.uniform(-np.pi, np.pi, 6)])
    dxu = np.vstack([rng.uniform(-0.2, 0.2, 6), rng.uniform(-2, 2, 6)])
    for certificate in (
        create_robust_barriers(),
        certificates.create_unicycle_differential_drive_barrier_certificate_with_boundary(),
    ):
        out = certificate(dxu, x)
        wheels = np.vstack([out[0] / 0.008 - out[1] * 0.105 / 0.032, out[0] / 0.008 + out[1] * 0.105 / 0.032]) / 2
        assert np.abs(wheels).max() <= 12.5 + 1e-6
        assert certificate.stats.solves == 1 and certificate.stats.failures == 0
    calm = np.zeros((2, 6))
    far = np.vstack([np.linspace(-1.2, 1.2, 6), np.zeros(6), np.zeros(6)])
    np.testing.assert_array_equal(create_robust_barriers()(calm, far), calm)


# ---------------------------------------------------------------------- the alias


def run_alias(tmp_path, source: str) -> subprocess.CompletedProcess:
    script = tmp_path / 'script.py'
    script.write_text(textwrap.dedent(source), encoding='utf-8')
    return subprocess.run(
        [sys.executable, '-m', 'robotarium_exp.rps_alias', '--classic', '--seed', '0', str(script)],
        capture_output=True,
        text=True,
        env=dict(
            os.environ, MPLBACKEND='Agg', PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get('PYTHONPATH', '')])
        ),
        cwd=tmp_path,
        timeout=120,
        check=False,
    )


def test_si_go_to_point_loop_ends_with_the_classic_report(tmp_path) -> None:
    done = run_alias(
        tmp_path,
        """
        import numpy as np
        import rps.robotarium as robotarium
        from rps.utilities.transformations import *
        from rps.utilities.barrier_certificates import *
        from rps.utilities.misc import *
        from rps.utilities.controllers import *

        N = 5
        initial_conditions = np.array([[1, 0.5, -0.5, 0, 0.28], [0.8, -0.3, -0.75, 0.1, 0.34], [0, 0, 0, 0, 0.0]])
        r = robotarium.Robotarium(number_of_robots=N, show_figure=True, initial_conditions=initial_conditions,
                                  sim_in_real_time=False)
        goal_points = generate_initial_conditions(N)
        controller = create_si_position_controller()
        barrier = create_single_integrator_barrier_certificate_with_boundary()
        _, uni_to_si_states = create_si_to_uni_mapping()
        si_to_uni_dyn = create_si_to_uni_dynamics_with_backwards_motion()
        x = r.get_poses()
        x_si = uni_to_si_states(x)
        r.step()
        while np.size(at_pose(np.vstack((x_si, x[2, :])), goal_points, rotation_error=100)) != N:
            x = r.get_poses()
            x_si = uni_to_si_states(x)
            dxi = barrier(controller(x_si, goal_points[:2, :]), x_si)
            r.set_velocities(np.arange(N), si_to_uni_dyn(dxi, x))
            r.step()
        print(type(plt).__name__, r.time_step, r.boundaries)
        r.call_at_scripts_end()
        """,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    lines = done.stdout.splitlines()
    assert lines[0] == 'module 0.033 [-1.6, -1, 3.2, 2]' and lines[1] == '##### DEBUG OUTPUT #####'
    assert lines[2].startswith('Your simulation will take approximately ') and lines[2].endswith(
        ' real seconds when deployed on the Robotarium. '
    )
    assert 5 <= int(lines[2].split()[5]) <= 60


@pytest.mark.skipif(hasattr(np, 'mat'), reason='np.mat exists before numpy 2')
def test_np_mat_failure_names_the_fix(tmp_path) -> None:
    done = run_alias(tmp_path, "import numpy as np\nic = np.array(np.mat('1 0.5; 0.8 -0.3'))\n")
    assert done.returncode == 1
    last = done.stderr.strip().splitlines()[-1]
    assert 'np.mat' in last and 'np.asmatrix' in last and 'np.array(' in last and 'script.py' in last
