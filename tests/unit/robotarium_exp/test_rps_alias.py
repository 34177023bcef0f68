"""The API contract with the official Robotarium simulator V2: every public name, its signature, its constants.

``V2_SIGNATURES`` is V2's public interface as data: for each function and method of ``rps.robotarium``,
``rps.robotarium_abc``, ``rps.utilities.*`` and the ``rps.examples`` EKF helper, its parameters as
(name, kind, default) with kind ``pk`` positional-or-keyword, ``k`` keyword-only, ``**`` variadic keywords and the
default's ``repr``. It was recorded by introspecting the official package (facts, not its code). V2's constructors
take ``**kwargs`` and read the keywords of ``V2_ROBOTARIUM_KEYWORDS``; ours name them as keyword-only parameters
with the same defaults.

The behaviour behind the names is pinned elsewhere against V2's recorded outputs: dynamics, encoder counts and the
initialization (``test_rps.py``), the controllers and maps (``test_rps_utilities.py``), the distance sensors
(``test_rps_sensors.py``), the barrier certificates (``test_barrier.py``).
"""

from __future__ import annotations

import importlib
import inspect
import sys
from typing import Any

import cvxopt
import numpy as np
import pytest

from robotarium_exp import rps_alias, rps_import

V2_SIGNATURES: dict[str, list[tuple[str, str, str | None]]] = {
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:UnicycleEKF.__init__': [
        ('self', 'pk', None),
        ('initial_state', 'pk', None),
        ('initial_covariance', 'pk', None),
        ('b', 'pk', None),
        ('r', 'pk', None),
        ('M', 'pk', None),
        ('Q', 'pk', None),
    ],
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:UnicycleEKF.form_F': [
        ('self', 'pk', None),
        ('v', 'pk', None),
        ('dt', 'pk', None),
    ],
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:UnicycleEKF.form_G': [
        ('self', 'pk', None),
        ('dt', 'pk', None),
    ],
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:UnicycleEKF.form_Q': [
        ('self', 'pk', None),
        ('dt', 'pk', None),
    ],
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:UnicycleEKF.form_fx': [
        ('self', 'pk', None),
        ('v', 'pk', None),
        ('w', 'pk', None),
        ('dt', 'pk', None),
    ],
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:UnicycleEKF.form_wheel_encoder_process_noise_matrix': [
        ('self', 'pk', None),
        ('dt', 'pk', None),
    ],
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:UnicycleEKF.predict': [
        ('self', 'pk', None),
        ('v', 'pk', None),
        ('w', 'pk', None),
        ('dt', 'pk', None),
    ],
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:UnicycleEKF.update_brearing': [
        ('self', 'pk', None),
        ('beacon_position', 'pk', None),
        ('bearing_measurement', 'pk', None),
        ('R_bearing', 'pk', 'None'),
    ],
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:UnicycleEKF.update_gps': [
        ('self', 'pk', None),
        ('gps_measurement', 'pk', None),
        ('R_gps', 'pk', None),
    ],
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:UnicycleEKF.update_gyro': [
        ('self', 'pk', None),
        ('yaw_rate', 'pk', None),
        ('dt', 'pk', None),
        ('R_gyro', 'pk', 'None'),
    ],
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:UnicycleEKF.update_orientation': [
        ('self', 'pk', None),
        ('orientation', 'pk', None),
        ('R_orientation', 'pk', 'None'),
    ],
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:UnicycleEKF.update_range': [
        ('self', 'pk', None),
        ('beacon_position', 'pk', None),
        ('range_measurement', 'pk', None),
        ('R_range', 'pk', None),
    ],
    'rps.examples.state_estimation.extended_kalman_filter.uni_ekf:wrap_angle': [('angle', 'pk', None)],
    'rps.robotarium:Robotarium.__init__': [('self', 'pk', None), ('kwargs', '**', None)],
    'rps.robotarium:Robotarium.debug': [('self', 'pk', None)],
    'rps.robotarium:Robotarium.get_poses': [('self', 'pk', None)],
    'rps.robotarium:Robotarium.initialize': [('self', 'pk', None), ('initial_conditions', 'pk', None)],
    'rps.robotarium:Robotarium.simulate_accelerations': [('self', 'pk', None)],
    'rps.robotarium:Robotarium.simulate_encoder_readings': [('self', 'pk', None)],
    'rps.robotarium:Robotarium.simulate_gyros': [('self', 'pk', None)],
    'rps.robotarium:Robotarium.simulate_magnetometers': [('self', 'pk', None)],
    'rps.robotarium:Robotarium.simulate_orientations': [('self', 'pk', None)],
    'rps.robotarium:Robotarium.step': [('self', 'pk', None)],
    'rps.robotarium_abc:ARobotarium.__init__': [('self', 'pk', None), ('kwargs', '**', None)],
    'rps.robotarium_abc:ARobotarium.debug': [('self', 'pk', None)],
    'rps.robotarium_abc:ARobotarium.get_accelerations': [('self', 'pk', None)],
    'rps.robotarium_abc:ARobotarium.get_distance_endpoints': [('self', 'pk', None)],
    'rps.robotarium_abc:ARobotarium.get_distances': [('self', 'pk', None)],
    'rps.robotarium_abc:ARobotarium.get_encoders': [('self', 'pk', None)],
    'rps.robotarium_abc:ARobotarium.get_gyros': [('self', 'pk', None)],
    'rps.robotarium_abc:ARobotarium.get_magnetic_fields': [('self', 'pk', None)],
    'rps.robotarium_abc:ARobotarium.get_orientations': [('self', 'pk', None)],
    'rps.robotarium_abc:ARobotarium.get_poses': [('self', 'pk', None)],
    'rps.robotarium_abc:ARobotarium.initialize': [('self', 'pk', None), ('initial_conditions', 'pk', None)],
    'rps.robotarium_abc:ARobotarium.robot_colormap': [('self', 'pk', None)],
    'rps.robotarium_abc:ARobotarium.set_velocities': [
        ('self', 'pk', None),
        ('ids', 'pk', None),
        ('velocities', 'pk', None),
    ],
    'rps.robotarium_abc:ARobotarium.step': [('self', 'pk', None)],
    'rps.utilities.barrier_certificates:_solve_qp': [
        ('N', 'pk', None),
        ('vhat', 'pk', None),
        ('A', 'pk', None),
        ('b', 'pk', None),
    ],
    'rps.utilities.barrier_certificates:create_si_barrier_certificate': [
        ('safety_radius', 'pk', '0.15'),
        ('barrier_gain', 'pk', '100.0'),
        ('magnitude_limit', 'pk', '0.2'),
    ],
    'rps.utilities.barrier_certificates:create_si_barrier_certificate_with_boundary': [
        ('safety_radius', 'pk', '0.15'),
        ('barrier_gain', 'pk', '100.0'),
        ('magnitude_limit', 'pk', '0.2'),
        ('boundary_points', 'pk', 'None'),
    ],
    'rps.utilities.barrier_certificates:create_uni_barrier_certificate': [
        ('barrier_gain', 'pk', '100.0'),
        ('safety_radius', 'pk', '0.15'),
        ('projection_distance', 'pk', '0.05'),
        ('velocity_magnitude_limit', 'pk', '0.2'),
    ],
    'rps.utilities.barrier_certificates:create_uni_barrier_certificate_with_boundary': [
        ('safety_radius', 'pk', '0.12'),
        ('barrier_gain', 'pk', '150.0'),
        ('projection_distance', 'pk', '0.03'),
        ('velocity_magnitude_limit', 'pk', '0.2'),
        ('boundary_points', 'pk', 'None'),
    ],
    'rps.utilities.controllers:create_pose_controller_clf': [
        ('approach_angle_gain', 'pk', '1'),
        ('desired_angle_gain', 'pk', '2.7'),
        ('rotation_error_gain', 'pk', '1'),
        ('wheel_velocity_limit', 'pk', '10.0'),
        ('wheel_radius', 'pk', '0.016'),
        ('base_length', 'pk', '0.105'),
    ],
    'rps.utilities.controllers:create_pose_controller_hybrid': [
        ('linear_velocity_gain', 'pk', '0.8'),
        ('angular_velocity_limit', 'pk', '3.141592653589793'),
        ('velocity_magnitude_limit', 'pk', '0.15'),
        ('position_error', 'pk', '0.03'),
        ('position_epsilon', 'pk', '0.01'),
        ('rotation_error', 'pk', '0.05'),
    ],
    'rps.utilities.controllers:create_pose_parking_controller_clf': [
        ('approach_angle_gain', 'pk', '1'),
        ('desired_angle_gain', 'pk', '2.7'),
        ('rotation_error_gain', 'pk', '1'),
        ('wheel_velocity_limit', 'pk', '10.0'),
        ('wheel_radius', 'pk', '0.016'),
        ('base_length', 'pk', '0.105'),
        ('position_error', 'pk', '0.05'),
        ('rotation_error', 'pk', '0.2'),
    ],
    'rps.utilities.controllers:create_pose_parking_controller_hybrid': [
        ('linear_velocity_gain', 'pk', '0.8'),
        ('angular_velocity_limit', 'pk', '3.141592653589793'),
        ('velocity_magnitude_limit', 'pk', '0.15'),
        ('position_error', 'pk', '0.05'),
        ('position_epsilon', 'pk', '0.01'),
        ('rotation_error', 'pk', '0.2'),
    ],
    'rps.utilities.controllers:create_si_position_controller': [
        ('x_velocity_gain', 'pk', '0.8'),
        ('y_velocity_gain', 'pk', '0.8'),
        ('velocity_magnitude_limit', 'pk', '0.15'),
    ],
    'rps.utilities.controllers:create_uni_position_controller': [
        ('x_velocity_gain', 'pk', '0.8'),
        ('y_velocity_gain', 'pk', '0.8'),
        ('velocity_magnitude_limit', 'pk', '0.15'),
        ('projection_distance', 'pk', '0.03'),
    ],
    'rps.utilities.graph:completeGL': [('n', 'pk', None)],
    'rps.utilities.graph:cycleGL': [('n', 'pk', None)],
    'rps.utilities.graph:delta_disk_neighbors': [('poses', 'pk', None), ('agent', 'pk', None), ('delta', 'pk', None)],
    'rps.utilities.graph:lineGL': [('n', 'pk', None)],
    'rps.utilities.graph:randomGL': [('v', 'pk', None), ('e', 'pk', None)],
    'rps.utilities.graph:random_connectedGL': [('v', 'pk', None), ('e', 'pk', None)],
    'rps.utilities.graph:topological_neighbors': [('L', 'pk', None), ('agent', 'pk', None)],
    'rps.utilities.misc:create_at_pose': [('position_error', 'pk', '0.05'), ('rotation_error', 'pk', '0.2')],
    'rps.utilities.misc:create_at_position': [('position_error', 'pk', '0.05')],
    'rps.utilities.misc:determine_font_size': [('robotarium_instance', 'pk', None), ('font_height_meters', 'pk', None)],
    'rps.utilities.misc:generate_initial_poses': [('N', 'pk', None), ('width', 'pk', '3.0'), ('height', 'pk', '1.0')],
    'rps.utilities.misc:generate_random_poses': [
        ('N', 'pk', None),
        ('spacing', 'pk', '0.5'),
        ('width', 'pk', '3.0'),
        ('height', 'pk', '1.8'),
    ],
    'rps.utilities.misc:generate_random_positions': [
        ('N', 'pk', None),
        ('spacing', 'pk', '0.5'),
        ('width', 'pk', '3.0'),
        ('height', 'pk', '1.8'),
    ],
    'rps.utilities.misc:rotation_matrix': [('theta', 'pk', None)],
    'rps.utilities.misc:unique_filename': [('file_name', 'pk', None)],
    'rps.utilities.sensors:simulate_distance_sensors': [
        ('poses', 'pk', None),
        ('obstacles', 'pk', None),
        ('distance_sensors_orientation', 'pk', None),
        ('robot_diameter', 'pk', None),
        ('robot_center_offset', 'pk', None),
        ('distance_sensor_range', 'pk', None),
        ('distance_sensor_error', 'pk', None),
        ('distance_sensor_dropout_prob', 'pk', None),
        ('distance_sensor_outlier_prob', 'pk', None),
    ],
    'rps.utilities.sensors:simulate_distance_sensors_without_robots': [
        ('poses', 'pk', None),
        ('obstacles', 'pk', None),
        ('distance_sensors_orientation', 'pk', None),
        ('distance_sensor_range', 'pk', None),
        ('distance_sensor_error', 'pk', None),
        ('distance_sensor_dropout_prob', 'pk', None),
        ('distance_sensor_outlier_prob', 'pk', None),
    ],
    'rps.utilities.transformations:create_si_to_uni_dynamics': [
        ('linear_velocity_gain', 'pk', '1'),
        ('angular_velocity_limit', 'pk', '3.141592653589793'),
    ],
    'rps.utilities.transformations:create_si_to_uni_dynamics_with_backwards_motion': [
        ('linear_velocity_gain', 'pk', '1'),
        ('angular_velocity_limit', 'pk', '3.141592653589793'),
    ],
    'rps.utilities.transformations:create_si_to_uni_mapping': [('projection_distance', 'pk', '0.05')],
    'rps.utilities.transformations:create_uni_to_si_mapping': [('projection_distance', 'pk', '0.05')],
}

V2_ROBOTARIUM_KEYWORDS = {
    'number_of_robots': -1,
    'show_figure': False,
    'initial_conditions': 'array([], dtype=float64)',
    'use_distance_sensors': False,
    'obstacles': None,
    'sim_in_real_time': True,
    'skip_initialization': False,
    'show_arena_boundaries': True,
    'show_robot_patches': True,
    'show_distance_endpoints': True,
    'show_distance_rays': False,
    'show_obstacles': True,
}
"""What V2's ``Robotarium(**kwargs)`` reads, with its defaults (``ARobotarium`` the same, but 0 robots)."""

V2_CONSTANTS = {
    'TIME_STEP': 0.033,
    'MAX_LINEAR_VELOCITY': 0.2,
    'ROBOT_DIAMETER': 0.11,
    'WHEEL_RADIUS': 0.016,
    'BASE_LENGTH': 0.11,
    'COLLISION_DIAMETER': 0.135,
    'COLLISION_OFFSET': 0.025,
    'BOUNDARIES': [-1.6, 1.6, -1.0, 1.0],
    'CENTER_OFFSET': 0.01,
    'DISTANCE_SENSOR_ERROR': 0.03,
    'DISTANCE_SENSOR_DROPOUT_PROB': 0.035,
    'DISTANCE_SENSOR_OUTLIER_PROB': 0.014,
    'DISTANCE_SENSOR_RANGE': 1.2,
    'ENCODER_COUNTS_PER_REVOLUTION': 28,
    'MOTOR_GEAR_RATIO': 100.37,
    'IMU_ORIENTATION': [0.05621, -0.0130372, 0.0],
    'ENCODER_NOISE_STD': 0.25,
    'ACCELEROMETER_NOISE_STDS': [0.012929, 0.012127, 0.052979],
    'GYRO_NOISE_STDS': [0.001663, 0.001216, 0.002372],
    'MAGNETOMETER_NOISE_STDS': [3.275843, 2.365798, 5.232685],
    'MAGNETOMETER_Z_AVG': -39.8594,
    'MAGNETOMETER_XY_AVG': 6.0712,
    'ORIENTATION_NOISE_STD': 0.31083,
    'MAX_WHEEL_VELOCITY': 12.5,
    'MAX_ANGULAR_VELOCITY': 3.6363636363636362,
}

KIND = {
    inspect.Parameter.POSITIONAL_OR_KEYWORD: 'pk',
    inspect.Parameter.KEYWORD_ONLY: 'k',
    inspect.Parameter.VAR_KEYWORD: '**',
    inspect.Parameter.VAR_POSITIONAL: '*',
    inspect.Parameter.POSITIONAL_ONLY: 'p',
}


def ours(qualified: str) -> Any:
    """Our object for ``rps.module:Name`` or ``rps.module:Class.method``."""
    module_name, name = qualified.split(':')
    module = importlib.import_module('robotarium_exp.' + module_name)
    obj: Any = module
    for part in name.split('.'):
        obj = getattr(obj, part)
    return obj


def parameters(function: Any) -> list[tuple[str, str, str | None]]:
    return [
        (p.name, KIND[p.kind], None if p.default is inspect.Parameter.empty else repr(p.default))
        for p in inspect.signature(function).parameters.values()
    ]


CONSTRUCTORS = ('rps.robotarium:Robotarium.__init__', 'rps.robotarium_abc:ARobotarium.__init__')


@pytest.mark.parametrize('qualified', sorted(set(V2_SIGNATURES) - set(CONSTRUCTORS)))
def test_every_v2_name_exists_with_v2s_signature(qualified: str) -> None:
    assert parameters(ours(qualified)) == V2_SIGNATURES[qualified]


@pytest.mark.parametrize(('qualified', 'robots'), [(CONSTRUCTORS[0], -1), (CONSTRUCTORS[1], 0)])
def test_constructors_take_v2s_keywords_with_v2s_defaults(qualified: str, robots: int) -> None:
    assert V2_SIGNATURES[qualified] == [('self', 'pk', None), ('kwargs', '**', None)]  # V2 reads **kwargs
    named = {name: default for name, kind, default in parameters(ours(qualified)) if kind == 'k'}
    expected = {name: repr(default) for name, default in V2_ROBOTARIUM_KEYWORDS.items()}
    expected['initial_conditions'] = V2_ROBOTARIUM_KEYWORDS['initial_conditions']
    expected['number_of_robots'] = repr(robots)
    if qualified == CONSTRUCTORS[1]:  # the shared part knows nothing of timing and initialization
        del expected['sim_in_real_time'], expected['skip_initialization']
    else:  # beyond V2: what the real robots do (robotarium_exp.rps.testbed_model), ideal by default
        expected['testbed_model'] = repr('ideal')
    assert named == expected


@pytest.mark.parametrize('name', sorted(V2_CONSTANTS))
def test_constants_are_v2s(name: str) -> None:
    from robotarium_exp.rps.robotarium import Robotarium
    from robotarium_exp.rps.robotarium_abc import ARobotarium

    for cls in (ARobotarium, Robotarium):
        value = getattr(cls, name)
        np.testing.assert_allclose(value, V2_CONSTANTS[name], rtol=1e-15)
        assert isinstance(value, np.ndarray) == isinstance(V2_CONSTANTS[name], list)  # arrays stay arrays


def test_the_alias_maps_every_v2_module() -> None:
    """``rps_alias`` registers each module of the table under its ``rps`` name."""
    mapped = {'rps' + suffix for suffix in rps_import.V2.modules}
    assert {key.split(':')[0] for key in V2_SIGNATURES} <= mapped


# ---------------------------------------------------------------------- the alias itself, in-process


@pytest.mark.usefixtures('clean_rps')
@pytest.mark.parametrize('classic', [False, True])
def test_install_resolves_each_rps_name_to_the_generations_module(classic: bool, tmp_path) -> None:
    rps_alias.install(classic=classic, log_path=str(tmp_path / 'log.npz'))
    generation = rps_import.CLASSIC if classic else rps_import.V2
    for suffix in generation.modules:
        module = importlib.import_module('rps' + suffix)
        ours = importlib.import_module(generation.package + suffix)
        if hasattr(ours, '__path__'):  # a package: an empty one of its own, as the official packages are
            assert module is not ours and module.__doc__ == ours.__doc__
        elif suffix != '.robotarium':
            assert module is ours
    simulator = importlib.import_module(generation.package + '.robotarium')
    recorded = sys.modules['rps.robotarium'].Robotarium
    assert issubclass(recorded, simulator.Robotarium) and recorded is not simulator.Robotarium  # it records
    assert sys.modules['rps'].robotarium is sys.modules['rps.robotarium']
    assert ('rps.utilities.barrier_certificates2' in sys.modules) is classic


def test_seeding_draws_the_same_numbers() -> None:
    import random

    rps_alias.seed_rps(12)
    first = (random.random(), np.random.rand())
    rps_alias.seed_rps(12)
    assert (random.random(), np.random.rand()) == first


@pytest.mark.usefixtures('clean_rps')
def test_main_runs_the_script_with_its_arguments_and_the_chosen_solver(tmp_path, monkeypatch, capsys) -> None:
    script = tmp_path / 'which.py'
    script.write_text(
        'import sys\nimport rps.robotarium\n'
        'from rps.utilities.barrier_certificates import qp_solver\n'
        'print(qp_solver(), sys.argv[1:], rps.robotarium.Robotarium.__module__)\n',
        encoding='utf-8',
    )
    monkeypatch.setattr(sys, 'argv', ['rps_alias', '--exact-qp', '--seed', '3', str(script), '--fast', '2'])
    rps_alias.main()
    assert capsys.readouterr().out == "exact ['--fast', '2'] robotarium_exp.rps.robotarium\n"


@pytest.mark.usefixtures('clean_rps')
def test_main_passes_the_testbed_model_to_every_robotarium(tmp_path, monkeypatch, capsys) -> None:
    script = tmp_path / 'model.py'
    script.write_text(
        'import numpy as np\nimport rps.robotarium as rr\n'
        'r = rr.Robotarium(number_of_robots=1, show_figure=False, sim_in_real_time=False,'
        ' initial_conditions=np.zeros((3, 1)), skip_initialization=True)\n'
        'print(r._testbed.model.name, r._testbed.model.delay_omega_steps, type(r).__name__)\n',
        encoding='utf-8',
    )
    monkeypatch.setattr(sys, 'argv', ['rps_alias', '--testbed-model', 'fitted:2', '--seed', '1', str(script)])
    rps_alias.main()
    delay = 2 * rps_alias.testbed_model('fitted').delay_omega_steps
    assert capsys.readouterr().out == f'fitted:2 {delay} Robotarium\n'


@pytest.mark.usefixtures('clean_rps')
def test_install_gives_the_classic_generation_its_testbed_model_too() -> None:
    rps_alias.install(classic=True, testbed_model='fitted')
    r = importlib.import_module('rps.robotarium').Robotarium(1, False, False, np.zeros((3, 1)))
    assert r._testbed.model is rps_alias.testbed_model('fitted') and hasattr(r, 'call_at_scripts_end')


@pytest.mark.parametrize(
    ('argv', 'message'),
    [
        (['--testbed-model', 'fitted:0', 'x.py'], "the scale '0' is not a number > 0"),
        (['--testbed-model', 'real', 'x.py'], "'ideal', 'fitted' or 'fitted:K'"),
        ([], 'give the script to run'),
        (['missing.py'], 'missing.py: no such script'),
        (['--seed', '-1', 'x.py'], "'-1' is not a seed from 0 to 2**32 - 1"),
        (['bad.py'], 'bad.py is not a Python script'),
    ],
)
def test_main_refuses_what_it_cannot_run(argv: list[str], message: str, tmp_path, monkeypatch, capsys) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / 'bad.py').write_text('def (:\n', encoding='utf-8')
    monkeypatch.setattr(sys, 'argv', ['rps_alias', *argv])
    with pytest.raises(SystemExit) as exit_:
        rps_alias.main()
    assert exit_.value.code == 2 and message in capsys.readouterr().err


@pytest.mark.usefixtures('clean_rps')
def test_np_mat_is_named_with_its_fix(tmp_path, monkeypatch, capsys) -> None:
    script = tmp_path / 'old.py'
    script.write_text('import numpy as np\nnp.mat\n', encoding='utf-8')
    monkeypatch.setattr(sys, 'argv', ['rps_alias', str(script)])
    assert rps_alias.uses_np_mat(AttributeError("module 'numpy' has no attribute 'mat'"))
    assert not rps_alias.uses_np_mat(AttributeError('no attribute matrix_power'))
    if hasattr(np, 'mat'):
        rps_alias.main()  # numpy 1: nothing to name
        return
    with pytest.raises(SystemExit) as exit_:
        rps_alias.main()
    assert exit_.value.code == 1
    assert 'np.asmatrix' in capsys.readouterr().err


# ---------------------------------------------------------------------- scripts run as python runs them

QP_SCRIPT = """\
import sys
from cvxopt import matrix, solvers
import rps.robotarium
from helper import VALUE
print(VALUE, __file__ == sys.argv[1], sys.argv[2:])
for _ in range(3):
    solvers.qp(matrix([[2.0, 0.0], [0.0, 2.0]]), matrix([-2.0, -1.0]), matrix([[1.0], [1.0]]), matrix([0.5]))
print(sorted(solvers.options.items()))
"""
"""A script beside its own module, solving its own QPs with cvxopt after importing ``rps.robotarium``."""

QP_OUTPUT_LINES = {False: 2, True: 23}
"""Its output's lines on the official simulators (recorded): V2's rps.robotarium sets cvxopt's options, so only the
script's two lines; classic's does not, so cvxopt also prints its progress (7 lines a solve)."""


@pytest.mark.usefixtures('clean_rps')
@pytest.mark.parametrize('classic', [False, True])
def test_a_script_runs_as_python_runs_it(classic: bool, tmp_path, monkeypatch, capsys) -> None:
    folder = tmp_path / 'mine'
    folder.mkdir()
    (folder / 'helper.py').write_text('VALUE = 7\n', encoding='utf-8')
    (folder / 'qp.py').write_text(QP_SCRIPT, encoding='utf-8')
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, 'path', [str(tmp_path), *sys.path[1:]])  # as python -m leaves it: the cwd first
    argv = ['rps_alias', *(['--classic'] if classic else []), 'mine/qp.py', str(folder / 'qp.py'), 'x']
    monkeypatch.setattr(sys, 'argv', argv)
    cvxopt.solvers.options.clear()  # a fresh interpreter's (an official rps imported in this process sets them)
    rps_alias.main()
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == QP_OUTPUT_LINES[classic] and lines[0] == "7 True ['x']"
    assert sys.path[0] == str(folder)
    if not classic:
        assert lines[-1] == str(sorted(rps_import.OFFICIAL_QP_OPTIONS.items()))


@pytest.mark.usefixtures('clean_rps')
@pytest.mark.parametrize(
    ('classic', 'source', 'hint'),
    [
        (False, 'from rps.utilities.graph import cycle_GL\n', 'cycle_GL from rps.utilities.graph'),
        (False, 'from rps.utilities import barrier_certificates2\n', 'barrier_certificates2 from rps.utilities'),
        (False, 'import rps.utilities.barrier_certificates2\n', 'the module rps.utilities.barrier_certificates2'),
        (True, 'from rps.utilities.graph import cycleGL\n', 'cycleGL from rps.utilities.graph'),
    ],
)
def test_a_name_of_the_other_generation_is_one_line_naming_classic(
    classic: bool, source: str, hint: str, tmp_path, monkeypatch, capsys
) -> None:
    script = tmp_path / 'names.py'
    script.write_text(source, encoding='utf-8')
    monkeypatch.setattr(sys, 'argv', ['rps_alias', *(['--classic'] if classic else []), str(script)])
    with pytest.raises(SystemExit) as exit_:
        rps_alias.main()
    err = capsys.readouterr().err
    generation, fix = (
        ('V2', f'without --classic: python -m robotarium_exp.rps_alias {script}')
        if classic
        else (
            'classic',
            f'with --classic: python -m robotarium_exp.rps_alias --classic {script}',
        )
    )
    assert exit_.value.code == 1 and err.count('\n') == 1 and 'Traceback' not in err
    assert f'imports {hint}, which only the {generation} generation of rps has; run it {fix}' in err


@pytest.mark.usefixtures('clean_rps')
def test_a_name_neither_generation_has_keeps_pythons_error(tmp_path, monkeypatch) -> None:
    script = tmp_path / 'typo.py'
    script.write_text('from rps.utilities.graph import cycle_gl\n', encoding='utf-8')
    monkeypatch.setattr(sys, 'argv', ['rps_alias', str(script)])
    with pytest.raises(ImportError, match="cannot import name 'cycle_gl'"):
        rps_alias.main()
