"""A submission run through the alias, analysed from its files (which record the flight's start) and from its
simulator log (which does not)."""

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
    for key in ('min_distance_m', 'collision_pairs', 'extent_at_narrowing_m'):
        assert from_files[key] == pytest.approx(from_log[key], abs=1e-12)
    # the log holds what each step() validated; the files also the poses after the last step (the script's last
    # get_poses()), which no step validates
    assert from_files['frames'] == from_log['frames'] + 1
    # the files count a robot's body on the walls, the log (no recorded start) its centre: neither touches
    assert from_files['collision_pairs'] == 0 and from_files['tube_violation_steps'] == 0
    assert from_log['tube_violation_steps'] == 0
    # the files record the flight's start: timed as the experiment times it; the simulator's log does not (inferred,
    # and its robots start inside the tube), but it saw the same entry and exits (a 'bundled robotarium' log, not a
    # simulation's, which is timed from its first row)
    assert from_files['passage']['start'].startswith('start recorded by the flight at t = 0.00 s')
    assert from_log['passing_time_s'] is None and from_log['passage']['start'].startswith('start inferred')
    observed = from_log['last_exit_s'] - from_log['first_entry_s']
    assert from_files['passing_time_s'] == pytest.approx(observed, abs=1e-9) and observed > 0
    assert from_files['tube_violation_body_radius_m'] > 0 and from_log['tube_violation_body_radius_m'] == 0
    strict = analyse(load_trajectory([tmp_path]), scene, collision_distance_m=1.0).metrics.to_json()  # a larger radius
    assert strict['collision_distance_m'] == 1.0 and strict['collision_pairs'] > 0
