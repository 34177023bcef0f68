"""A submission run through the alias, analysed from its files and from its simulator log."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from robotarium_exp.analysis.loaders import load_trajectory
from robotarium_exp.analysis.report import analyse
from robotarium_exp.scene import load_scene

ROOT = Path(__file__).resolve().parents[2]


def test_submission_files_analyse_like_the_simulator_log_of_the_same_run(tmp_path) -> None:
    run = subprocess.run(
        [
            sys.executable,
            '-m',
            'robotarium_exp.rps_alias',
            '--classic',
            '--seed',
            '0',
            '--log',
            str(tmp_path / 'sim.npz'),
            str(ROOT / 'submissions' / 'vtube_robotarium_trapezoid.py'),
        ],
        cwd=tmp_path,
        env={**__import__('os').environ, 'VTUBE_HEADLESS': '1', 'MPLBACKEND': 'Agg'},
        capture_output=True,
        text=True,
        check=True,
    )
    assert '"completed": true' in run.stdout
    scene = load_scene('robotarium_trapezoid')
    from_files = analyse(load_trajectory([tmp_path]), scene).metrics.to_json()
    from_log = analyse(load_trajectory([tmp_path / 'sim.npz']), scene).metrics.to_json()
    for key in (
        'passing_time_s',
        'min_distance_m',
        'collision_pairs',
        'tube_violation_steps',
        'frames',
        'extent_at_narrowing_m',
    ):
        assert from_files[key] == pytest.approx(from_log[key], abs=1e-12)
    assert from_files['collision_pairs'] == 0 and from_files['tube_violation_steps'] == 0
    strict = analyse(load_trajectory([tmp_path]), scene, collision_distance_m=1.0).metrics.to_json()  # a larger radius
    assert strict['collision_distance_m'] == 1.0 and strict['collision_pairs'] > 0
