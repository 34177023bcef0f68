"""Issue 49's newcomer: an own 8-robot L-shaped tube whose `robotarium run` failed (bodies on a wall) while the
build's preflight of the same file said PASS. One verdict (`robotarium_exp.verdict.run_failures`) then failed both;
since the safety filter's wall rows hold the narrowing's closing in (issue 50), both fly it clean, and agree."""

from __future__ import annotations

from pathlib import Path

import pytest

L_TUBE = """title = "An own L-shaped tube"

[tube.center]
start_xy_m = [-1.45, -0.35]
heading_deg = 0.0
pieces = [{ kind = "line", length_m = 1.6 }, { kind = "arc", radius_m = 0.35, angle_deg = 90.0 },
    { kind = "line", length_m = 0.2 }]

[tube.width]
start_m = 0.5
parts = [
    { kind = "constant", length_m = 1.25 },
    { kind = "smooth", length_m = 0.3, to_m = 0.2 },
    { kind = "constant" },
]

[robotarium]
n_robots = 8
"""


@pytest.fixture(scope='module')
def l_tube(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The scene file and its plan."""
    from robotarium_exp.scene import load_scene
    from vtube.pipeline import plan_scene

    folder = tmp_path_factory.mktemp('l_tube')
    scene_file = folder / 'l_tube.toml'
    scene_file.write_text(L_TUBE, encoding='utf-8')
    assert load_scene(scene_file).swarm.n_robots == 8
    return scene_file, plan_scene(str(scene_file), folder / 'plan').plan_file


def test_the_run_and_the_preflight_of_the_same_tube_agree_and_keep_off_the_walls(
    l_tube: tuple[Path, Path], tmp_path: Path
) -> None:
    from robotarium_exp.experiment import run_experiment
    from robotarium_exp.rps.robotarium import Robotarium
    from robotarium_exp.rps_alias import seed_rps
    from robotarium_exp.scene import load_scene
    from robotarium_exp.verdict import flight_failures
    from submission.check import check
    from vtube.pipeline import build_submission, plan_for

    scene_file, plan_file = l_tube
    scene = load_scene(scene_file)
    seed_rps(0)
    flown = run_experiment(Robotarium, scene, plan_for(scene, plan_file=plan_file))
    assert flight_failures(flown) == () and flown.metrics is not None and flown.metrics.tube_violation_steps == 0
    built = build_submission(scene_file, tmp_path / 'experiment.py', plan_file=plan_file, declare=False)
    report = check(built.path, seeds=(0,), initializer_seeds=2, testbed_models=('ideal',))
    ideal = report.runs[0]
    assert ideal.metrics is not None and ideal.metrics.tube_violation_steps == 0
    assert report.problems == [] and report.passed
