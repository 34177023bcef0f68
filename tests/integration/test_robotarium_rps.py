"""Scripts on the bundled V2 simulator and the PyPI one, through the alias (subprocesses)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_the_same_script_runs_on_both_simulators_and_agrees(tmp_path) -> None:
    pytest.importorskip('rps.robotarium')  # the PyPI robotarium-python-simulator (test extra)
    script = ROOT / 'examples' / 'wander.py'
    env_plot = {'MPLBACKEND': 'Agg'}
    import os

    env = dict(os.environ, **env_plot)
    pypi = subprocess.run(
        [sys.executable, str(script), str(tmp_path / 'pypi.npy')], capture_output=True, text=True, env=env, check=True
    )
    bundled = subprocess.run(
        [sys.executable, '-m', 'robotarium_exp.rps_alias', '--classic', str(script), str(tmp_path / 'ours.npy')],
        capture_output=True,
        text=True,
        env=env,
        check=True,
        cwd=ROOT,
    )
    a, b = np.load(tmp_path / 'pypi.npy'), np.load(tmp_path / 'ours.npy')
    assert a.shape == b.shape == (300, 3, 6)
    np.testing.assert_allclose(b, a, atol=1e-9)  # step by step
    assert 'No errors in your simulation' in pypi.stdout and 'No errors in your simulation' in bundled.stdout


@pytest.mark.parametrize(('flags', 'solver'), [([], 'testbed'), (['--exact-qp'], 'exact')])
def test_the_alias_chooses_how_the_certificates_solve(tmp_path, flags: list[str], solver: str) -> None:
    """A script's certificates answer as the testbed's unless ``--exact-qp`` asks for the exact optimum."""
    script = tmp_path / 'which.py'
    script.write_text(
        'import numpy as np\n'
        'from rps.utilities.barrier_certificates import create_si_barrier_certificate, qp_solver\n'
        'x = np.array([[0.0, 1.0], [0.0, 0.0]])\n'
        'u = create_si_barrier_certificate()(np.array([[0.1, 0.0], [0.0, 0.0]]), x)\n'
        'print(qp_solver(), repr(float(u[0, 0])))\n',
        encoding='utf-8',
    )
    result = subprocess.run(
        [sys.executable, '-m', 'robotarium_exp.rps_alias', *flags, str(script)],
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
    )
    name, first = result.stdout.split()
    assert name == solver
    assert (float(first) == 0.1) == (solver == 'exact')  # a feasible command: unchanged only when solved exactly
