"""``vtube demo``: the whole way, plan to report, on the bundled simulator (one run, shared: ``demo_run``)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from robotarium_exp.experiment import run_experiment
from robotarium_exp.spec import ROBOTARIUM
from vtube.cli.app import main
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


def test_the_returned_file_flies_the_bundled_experiment_and_compare_writes_the_table(
    demo_run, tmp_path, capsys, monkeypatch
) -> None:
    """``vtube robotarium compare`` flies the bundled experiment of the demo's scene and plan on V2's seed-0 draws:
    the built file that the demo ran as the testbed would flies the same poses."""
    import robotarium_exp.compare as compare_module

    flown = []

    def kept(*args, **kwargs):
        flown.append(run_experiment(*args, **kwargs))
        return flown[-1]

    monkeypatch.setattr(compare_module, 'run_experiment', kept)
    assert main(['robotarium', 'compare', DEMO_SCENE, '--seeds', '1', '--out', str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert '| measure | planned | unplanned |' in out and '| expansion starts [s] |' in out
    rows = json.loads((tmp_path / f'compare_{DEMO_SCENE}.json').read_text())
    assert [row['planned'] for row in rows] == [True, False]
    assert rows[1]['expansion_start_s'] is None and rows[0]['expansion_start_s'] > 0
    assert (tmp_path / f'compare_{DEMO_SCENE}.md').read_text().count('\n') == 12

    experiment, planned = flown[0], demo_run.stage(Planned)
    assert experiment.planned and planned.scene.name == DEMO_SCENE
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
    assert returned.passing_time_s == pytest.approx(mine.passing_time_s, rel=0.01)
    assert returned.min_distance_m == pytest.approx(mine.min_distance_m, abs=0.005)
    assert returned.tube_violation_steps == pytest.approx(mine.tube_violation_steps, rel=0.05)
    np.testing.assert_allclose(positions, experiment.arrays['positions_m'], atol=1e-9)  # in fact, the same trajectory
