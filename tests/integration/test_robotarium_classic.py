"""Scripts run through the alias on the classic generation (subprocesses)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


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
