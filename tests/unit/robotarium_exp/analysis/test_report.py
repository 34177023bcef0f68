"""The analysis report: passage, typed metrics and their JSON, the CLI without a tube."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.analysis.report import analyse
from robotarium_exp.scene import load_scene
from tests.support.bags import truth, write_bag


def passage_of(x: np.ndarray, y: np.ndarray, dt: float = 0.1):
    """Analysis in the trapezoid scene (a straight tube from x = -1.45 to 1.0 along y = 0) of robots at x, y (T, N)."""
    from robotarium_exp.analysis.trajectory import RobotSamples, assemble

    stamps = np.arange(x.shape[0], dtype=np.int64) * int(dt * 1e9)
    samples = {f'r{k}': RobotSamples(stamps, np.stack([x[:, k], y[:, k]], axis=1)) for k in range(x.shape[1])}
    return analyse(
        assemble(samples, source={'path': 'synthetic'}), load_scene('robotarium_trapezoid')
    ).metrics.to_json()


def test_passing_time_only_for_an_observed_passage() -> None:
    t = np.arange(400) * 0.1
    lanes = np.array([-0.2, 0.0, 0.2])
    x = -1.8 + 0.1 * t[:, None] - np.array([0.0, 0.3, 0.6])  # 0.1 m/s, the last robot 0.6 m behind
    y = np.broadcast_to(lanes, x.shape)
    m = passage_of(x, y)
    first_in = (-1.45 + 1.8) / 0.1  # analytic, on the 0.1 s frames
    last_out = (1.0 + 1.8 + 0.6) / 0.1
    assert m['passing_time_s'] == pytest.approx(last_out - first_in, abs=0.1 + 1e-9)
    assert m['passage']['unobserved'] == [] and m['completed']
    past = passage_of(x + 3.5, y)  # every robot past the exit at the first frame
    assert past['passing_time_s'] is None and not past['passage']['entrance_observed']
    assert set(past['passage']['never_inside']) == {'r0', 'r1', 'r2'}
    aside = y + np.array([0.0, 2.0, -2.0])  # two of three never enter
    m = passage_of(x, aside)
    assert m['passing_time_s'] is None and m['passage']['never_inside'] == ['r1', 'r2']
    assert 'never seen inside the tube: r1, r2' in m['passage']['unobserved']
    late = passage_of(x[:200], y[:200])  # the recording stops before the last robot leaves
    assert late['passing_time_s'] is None and late['passage']['not_exited']


def test_a_flight_that_recorded_its_start_is_timed_from_it_with_the_robots_bodies() -> None:
    """Three robots start inside the trapezoid's tube at x = -1.2, -1.3, -1.405 (l = 0.25, 0.15, 0.045) and leave it at
    x = 1.0 at 0.1 m/s; in the narrowing (half-width 0.25 m) the centre of r2 runs 0.03 m from the wall: its body is
    outside, its centre is not."""
    from robotarium_exp.analysis.trajectory import RobotSamples, assemble
    from robotarium_exp.spec import ROBOTARIUM

    t = np.arange(300) * 0.1
    x = -1.2 + 0.1 * t[:, None] - np.array([0.0, 0.1, 0.205])  # no frame exactly at the exit
    y = np.broadcast_to(np.array([-0.1, 0.05, 0.22]), x.shape)
    stamps = np.arange(300, dtype=np.int64) * 100_000_000
    samples = {f'r{k}': RobotSamples(stamps, np.stack([x[:, k], y[:, k]], axis=1)) for k in range(3)}
    start = {'iteration': 900, 'robotarium_time_s': 29.7, 't_s': 0.0}
    scene = load_scene('robotarium_trapezoid')
    recorded = analyse(assemble(samples, source={'path': 'flight', 'flight_start': start}), scene).metrics.tube
    inferred = analyse(assemble(samples, source={'path': 'other'}), scene).metrics.tube
    assert recorded is not None and inferred is not None
    last_out = (1.0 + 1.405) / 0.1  # analytic: the last robot reaches x = 1.0; the first is inside at t = 0
    assert recorded.passage.passing_time_s == pytest.approx(last_out, abs=0.1 + 1e-9)
    assert recorded.passage.start.startswith('start recorded by the flight at t = 0.00 s, after an initialization')
    assert inferred.passage.passing_time_s is None  # nobody seen before the entrance
    half = scene.tube.half_width(np.clip(x[:, 2] + 1.45, 0.0, scene.tube.length_m))
    inside = (x[:, 2] >= -1.45) & (x[:, 2] <= -1.45 + scene.tube.length_m)
    body = 0.5 * ROBOTARIUM.robot_diameter_m
    assert recorded.body_radius_m == body and inferred.body_radius_m == 0.0
    assert recorded.tube_violation_steps == int((inside & (half - 0.22 < body)).sum()) > 0
    assert inferred.tube_violation_steps == 0 and float(half.min()) == pytest.approx(0.25)


def test_typed_metrics_and_their_json_agree() -> None:
    from robotarium_exp.analysis.trajectory import RobotSamples, assemble

    t = np.arange(400) * 0.1
    x = -1.8 + 0.1 * t[:, None] - np.array([0.0, 0.3, 0.6])
    y = np.broadcast_to(np.array([-0.2, 0.0, 0.2]), x.shape)
    stamps = np.arange(400, dtype=np.int64) * 100_000_000
    samples = {f'r{k}': RobotSamples(stamps, np.stack([x[:, k], y[:, k]], axis=1)) for k in range(3)}
    trajectory = assemble(samples, source={'path': 'synthetic'})
    m = analyse(trajectory, load_scene('robotarium_trapezoid')).metrics
    data = m.to_json()
    assert m.tube is not None and m.tube.passage.passing_time_s == data['passing_time_s'] is not None
    assert m.closest is not None and list(m.closest.robots) == data['min_distance_pair']
    assert m.collision_pairs == data['collision_pairs'] == 0 and m.tube.tracking is None
    assert 'speed_tracking_mean_mps' not in data and data['plan'] is False
    tube_free = analyse(trajectory).metrics
    assert tube_free.tube is None and tube_free.colliding_pairs is None
    assert 'passage' not in tube_free.to_json()
    assert [p['frames_closer'] for p in tube_free.to_json()['pairs']] == [None, None, None]


def test_analysis_without_a_tube(tmp_path, capsys) -> None:
    from vtube.cli import main

    path = write_bag(tmp_path / 'b', 'mcap', 'tf')
    code = main(['analyze', str(path), '--out', str(tmp_path / 'a'), '--collision-distance', '0.31'])
    out = capsys.readouterr().out
    assert 'without a tube' in out and 'passing time' not in out
    _, xy, _ = truth()
    gaps = [np.hypot(*(xy[:, :, i] - xy[:, :, j]).T) for i, j in ((0, 1), (0, 2), (1, 2))]
    colliding = sum(int(g.min() < 0.31) for g in gaps)
    assert code == (1 if colliding else 0) and ('FAILED' in out) == bool(colliding)  # collisions are a failure
    closest = int(np.argmin([g.min() for g in gaps]))
    assert f'minimum distance {gaps[closest].min():.3f} m' in out
    assert f'{sum(int(g.min() < 0.31) for g in gaps)} pairs closer than 0.310 m' in out


def test_each_robots_clearance_from_the_scenes_obstacles(tmp_path) -> None:
    """Three robots along y = -0.2, 0 and 0.2 past a disc of radius 0.05 at (0, 0.45): their centres come 0.2, 0.4
    and 0.6 m from its rim, analytically; a robot through the disc touched it, and the analysis fails."""
    from dataclasses import replace

    from robotarium_exp.analysis.trajectory import RobotSamples, assemble
    from vtube_planning.geometry.obstacles import Disc, Obstacles

    scene = replace(load_scene('robotarium_trapezoid'), obstacles=Obstacles((Disc((0.0, 0.45), 0.05),)))
    t = np.arange(400) * 0.1
    x = -1.8 + 0.01 * np.arange(400)[:, None] + np.zeros(3)
    stamps = np.arange(400, dtype=np.int64) * 100_000_000

    def metrics(lanes):
        samples = {
            f'r{k}': RobotSamples(stamps, np.stack([x[:, k], np.full(t.size, lanes[k])], axis=1)) for k in range(3)
        }
        return analyse(assemble(samples, source={'path': 'synthetic'}), scene).metrics

    clear = metrics([0.2, 0.0, -0.2])
    np.testing.assert_allclose(clear.tube.obstacle_clearance_m, [0.2, 0.4, 0.6], atol=1e-12)
    assert clear.to_json()['obstacle_clearance_m'] == pytest.approx([0.2, 0.4, 0.6])
    assert not clear.failures()
    through = metrics([0.45, 0.0, -0.2])
    assert through.tube.obstacle_clearance_m[0] == 0.0 and through.failures() == ('robots r0 touched an obstacle',)
    assert load_scene('robotarium_trapezoid').obstacles == Obstacles()
    assert (
        analyse(
            assemble({'r0': RobotSamples(stamps, np.stack([x[:, 0], np.zeros(400)], axis=1))}, source={'path': 's'}),
            load_scene('robotarium_trapezoid'),
        ).metrics.tube.obstacle_clearance_m
        is None
    )


def test_a_simulation_log_is_timed_from_its_first_row_on_points_and_its_parking_is_apart(tmp_path) -> None:
    """Issue 49: the demo's planned simulation (31.040 s by `simulate`) showed no passing time beside the returned
    run; its log starts with the robots inside the tube. A simulation's log is timed from its first row, with point
    robots; the closest approach is given up to the last exit and after it (parking) apart."""
    from robotarium_exp.analysis.loaders import load_trajectory
    from vtube_planning.log import LogWriter

    t = np.arange(300) * 0.1
    x = -1.2 + 0.1 * t[:, None] - np.array([0.0, 0.1, 0.205])
    y = np.broadcast_to(np.array([-0.1, 0.05, 0.22]), x.shape).copy()
    y[280:, 1] = y[280:, 0] + 0.1  # parked: r0 and r1 0.1 m apart from t = 28.0 s, after the last exit
    log = LogWriter(tmp_path / 'sim.npz', {'kind': 'simulation', 'scene': 'robotarium_trapezoid'})
    for k in range(t.size):
        log.append(t_s=np.float64(t[k]), positions_m=np.stack([x[k], y[k]]))
    log.flush(finished=True)
    m = analyse(load_trajectory([tmp_path / 'sim.npz']), load_scene('robotarium_trapezoid')).metrics.tube
    assert m is not None
    last_out = (1.0 + 1.405) / 0.1
    assert m.passage.passing_time_s == pytest.approx(last_out, abs=0.1 + 1e-9) and m.body_radius_m == 0.0
    in_passage, parking = m.closest_in_passage, m.closest_after_passage
    assert in_passage is not None and parking is not None
    assert in_passage[1] <= m.passage.last_exit_s < parking[1] == pytest.approx(28.0)
    assert parking[0] == pytest.approx(np.hypot(0.1, 0.1)) and in_passage[0] == pytest.approx(np.hypot(0.1, 0.15))


def test_bodies_outside_the_workspace_before_the_exit_fail_the_recording() -> None:
    """Issue 49: `analyze` counts bodies outside the scene's workspace (the trapezoid's is the arena) over the whole
    run; a robot that leaves it before passing the exit fails the recording, one beyond the exit is counted apart."""
    from robotarium_exp.analysis.trajectory import RobotSamples, assemble

    t = np.arange(300) * 0.1
    x = -1.2 + 0.1 * t[:, None] - np.array([0.0, 0.3])
    y = np.zeros_like(x)
    y[100:110, 1] = 1.2  # r1 jumps off the arena (|y| <= 1) while inside the tube's span
    stamps = np.arange(300, dtype=np.int64) * 100_000_000
    samples = {f'r{k}': RobotSamples(stamps, np.stack([x[:, k], y[:, k]], axis=1)) for k in range(2)}
    start = {'iteration': 0, 'robotarium_time_s': 0.0, 't_s': 0.0}
    m = analyse(assemble(samples, source={'path': 'f', 'flight_start': start}), load_scene('robotarium_trapezoid'))
    contact = m.metrics.tube.map_contact
    assert contact is not None and contact.outside_workspace == 10 and contact.on_obstacles == 0
    beyond = int((x[:, 0] > 1.6 - 0.055).sum() + (x[:, 1] > 1.6 - 0.055).sum())  # past the exit, off the arena's end
    assert contact.outside_after_exit == beyond > 0
    assert any(
        f.startswith('robot bodies were outside the workspace (the map) in 10 robot-steps')
        for f in m.metrics.failures()
    )
    assert m.metrics.to_json()['map_contact']['outside_workspace'] == 10


def test_a_report_killed_while_it_draws_leaves_the_folder_as_it_was(tmp_path, monkeypatch) -> None:
    """Issue 49: a second `analyze` into the same --out, killed, left metrics.json of one input beside report.md of
    the other. The files are made in a hidden folder and moved in only when all are written."""
    import json

    import robotarium_exp.analysis.plots as analysis_plots
    from robotarium_exp.analysis.report import write_report
    from robotarium_exp.analysis.trajectory import RobotSamples, assemble

    def flight(lane: float):
        t = np.arange(100) * 0.1
        samples = {
            'r0': RobotSamples(np.arange(100, dtype=np.int64) * 100_000_000, np.stack([t, 0 * t + lane], axis=1))
        }
        return analyse(assemble(samples, source={'path': f'lane {lane}'}), None)

    out = tmp_path / 'report'
    write_report(out, {'data': flight(0.0)}, None, None)
    first = {p.name: p.read_bytes() for p in out.iterdir()}
    assert {'metrics.json', 'report.md'} <= set(first)

    def killed(*args, **kwargs):
        raise KeyboardInterrupt  # as a kill while the figures are drawn

    monkeypatch.setattr(analysis_plots, 'analysis_figures', killed)
    with pytest.raises(KeyboardInterrupt):
        write_report(out, {'data': flight(0.5)}, None, None)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == first  # nothing of the second run
    assert sorted(p.name for p in tmp_path.iterdir()) == ['report']  # no hidden folder left
    assert json.loads(first['metrics.json'])['data']['source']['path'] == 'lane 0.0'
