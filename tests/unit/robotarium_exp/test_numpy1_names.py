"""``--numpy1-names``: numpy 1's removed names given back, and a classic-era script built on ``np.mat`` runs."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from types import ModuleType

import numpy as np
import pytest

from robotarium_exp import rps_alias
from robotarium_exp.numpy1_names import NUMPY1_NAMES, missing, notice, provide

CLASSIC_SCRIPT = """\
import rps.robotarium as robotarium
from rps.utilities.transformations import *
from rps.utilities.barrier_certificates import *
from rps.utilities.misc import *
from rps.utilities.controllers import *

import numpy as np

# Three robots to three goals, start poses and goals typed as classic-era scripts type them
N = 3
initial_conditions = np.array(np.mat('1 0.5 -0.5; 0.8 -0.3 0.2; 0 0 0'))
r = robotarium.Robotarium(number_of_robots=N, show_figure=False, initial_conditions=initial_conditions,
                          sim_in_real_time=False)
goal_points = np.array(np.mat('-0.6 0.6 0.0; 0.3 0.3 -0.5; 0 0 0'))

single_integrator_position_controller = create_si_position_controller()
si_barrier_cert = create_single_integrator_barrier_certificate_with_boundary()
_, uni_to_si_states = create_si_to_uni_mapping()
si_to_uni_dyn = create_si_to_uni_dynamics_with_backwards_motion()

x = r.get_poses()
x_si = uni_to_si_states(x)
r.step()

steps = 0
while np.size(at_pose(np.vstack((x_si, x[2, :])), goal_points, rotation_error=100)) != N and steps < 2000:
    x = r.get_poses()
    x_si = uni_to_si_states(x)
    dxi = single_integrator_position_controller(x_si, goal_points[:2][:])
    dxi = si_barrier_cert(dxi, x_si)
    dxu = si_to_uni_dyn(dxi, x)
    r.set_velocities(np.arange(N), dxu)
    r.step()
    steps += 1

print(np.max(np.hypot(*(x_si - goal_points[:2]))), steps)
r.call_at_scripts_end()
"""
"""A script in the style of the classic examples (``np.array(np.mat('...'))`` start poses and goals)."""


@pytest.fixture
def numpy_as_installed() -> Iterator[None]:
    """What the test adds to ``numpy`` is taken away after it."""
    absent = set(missing(np))
    yield
    for name in absent & set(vars(np)):
        delattr(np, name)


@pytest.mark.usefixtures('numpy_as_installed')
def test_each_name_is_what_numpy_1_had_under_it_and_nothing_else_is_touched() -> None:
    fake = ModuleType('numpy_2_like')
    fake.asmatrix, fake.float64, fake.inf = np.asmatrix, np.float64, np.inf  # type: ignore[attr-defined]
    for new in set(NUMPY1_NAMES.values()):
        setattr(fake, new, getattr(np, new))
    before = dict(vars(fake))
    added = provide(fake)
    assert set(added) == set(NUMPY1_NAMES)
    assert fake.mat is np.asmatrix and fake.float_ is np.float64 and fake.NaN != fake.NaN  # type: ignore[attr-defined]
    assert {k: v for k, v in vars(fake).items() if k not in added} == before
    assert provide(fake) == {}  # a second time: all there, nothing added
    assert 'nothing added' in notice({}, '1.26.4') and 'np.mat (= np.asmatrix)' in notice(added, '2.2.0')


@pytest.mark.usefixtures('clean_rps', 'numpy_as_installed')
@pytest.mark.filterwarnings('ignore::PendingDeprecationWarning')  # np.matrix's, which Python hides by default
def test_a_classic_era_np_mat_script_runs_with_the_names_and_is_told_the_fix_without(
    tmp_path, monkeypatch, capsys
) -> None:
    script = tmp_path / 'go_to_goals.py'
    script.write_text(CLASSIC_SCRIPT, encoding='utf-8')
    if 'mat' not in vars(np):  # numpy 2: without the option the script stops, told both fixes
        monkeypatch.setattr(sys, 'argv', ['rps_alias', '--classic', '--seed', '0', str(script)])
        with pytest.raises(SystemExit) as stopped:
            rps_alias.main()
        err = capsys.readouterr().err
        assert stopped.value.code == 1 and f'--classic --numpy1-names {script}' in err
    monkeypatch.setattr(sys, 'argv', ['rps_alias', '--classic', '--numpy1-names', '--seed', '0', str(script)])
    rps_alias.main()
    captured = capsys.readouterr()
    assert captured.err.startswith('rps_alias: --numpy1-names: numpy ')
    distance, steps = captured.out.splitlines()[0].split()
    assert float(distance) < 0.05 and 0 < int(steps) < 2000  # at_pose's 0.05 m: all three arrived
