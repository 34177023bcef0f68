"""``vtube demo``: the whole way, plan to report, on the bundled simulator (one run, shared: ``demo_run``)."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.experiment import ExperimentConfig, run_experiment
from robotarium_exp.rps.robotarium import Robotarium
from robotarium_exp.rps_alias import seed_rps
from robotarium_exp.spec import ROBOTARIUM
from vtube.pipeline import DEMO_SCENE, Analysed, Planned, Returned, Simulated, WrittenSubmission
from vtube_planning.swarm.metrics import passage_metrics


def test_the_demo_runs_every_stage_and_reports_no_collision(demo_run) -> None:
    assert demo_run.code == 0, demo_run.err
    kinds = [type(stage) for stage in demo_run.stages]
    assert kinds == [Planned, Simulated, Simulated, WrittenSubmission, Returned, Analysed]
    assert [stage.result.planned for stage in demo_run.stages[1:3]] == [True, False]
    report = (demo_run.folder / 'report' / 'report.md').read_text()
    assert '| collision pairs | 0 |' in report and 'paths.png' in report
    titles = [line for line in demo_run.out.splitlines() if line.startswith('== ')]
    assert titles == [
        '== plan ==',
        '== simulate with planning ==',
        '== simulate without planning ==',
        '== build and check the submission ==',
        '== run the submission on the bundled simulator, as the testbed would, and analyse what it returns ==',
    ]
    assert demo_run.stage(Returned).ok and 'error:' not in demo_run.err


def test_the_returned_file_flies_the_bundled_experiment(demo_run) -> None:
    """Same scene and plan, same V2 initialization draws (seed 0): the experiment and the built file that the demo
    ran as the testbed would fly the same poses."""
    planned = demo_run.stage(Planned)
    seed_rps(0)
    experiment = run_experiment(Robotarium, planned.scene, planned.plan, ExperimentConfig())
    folder = demo_run.stage(Returned).folder
    positions, t = np.load(folder / 'vtube_positions_m.npy'), np.load(folder / 'vtube_t_s.npy')
    tube = planned.scene.tube
    robots = [tube.project(p) for p in positions]
    returned = passage_metrics(
        t,
        positions,
        np.array([p.l_m for p in robots]),
        np.array([p.clearance_m for p in robots]),
        tube.length_m,
        collision_distance_m=2 * planned.scene.swarm.r_p_m,
        body_radius_m=0.5 * ROBOTARIUM.robot_diameter_m,
    )
    mine = experiment.metrics
    assert planned.scene.name == DEMO_SCENE
    assert returned.passing_time_s == pytest.approx(mine.passing_time_s, rel=0.01)
    assert returned.min_distance_m == pytest.approx(mine.min_distance_m, abs=0.005)
    assert returned.tube_violation_steps == pytest.approx(mine.tube_violation_steps, rel=0.05)
    np.testing.assert_allclose(positions, experiment.arrays['positions_m'], atol=1e-9)  # in fact, the same trajectory
