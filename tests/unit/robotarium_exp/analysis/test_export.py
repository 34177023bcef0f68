"""A trajectory exported as a ROS 2 bag (MCAP, sqlite3) or CSV, and read back: the same frames, poses and metrics."""

from __future__ import annotations

import csv
import math
from dataclasses import replace

import numpy as np
import pytest
from rosbags.highlevel import AnyReader

from robotarium_exp.analysis.export import TUBE_TOPIC, _topic_name, _topic_names, export
from robotarium_exp.analysis.loaders import load_trajectory
from robotarium_exp.analysis.report import analyse
from robotarium_exp.errors import AnalysisError
from vtube_planning.geometry.scene import load_scene
from vtube_planning.swarm.simulate import SimConfig, simulate


@pytest.fixture(scope='module')
def flown(tmp_path_factory):
    """Scene A flown by six robots to the end (a passage to time), as its log, and that log read, with headings
    (the simulator's robots have none): the direction of motion."""
    scene = load_scene('A')
    log = tmp_path_factory.mktemp('flown') / 'log.npz'
    swarm = scene.swarm.__class__(**{**scene.swarm.__dict__, 'n_robots': 6})
    simulate(scene.tube, swarm, scene.control, plan=None, config=SimConfig(), log_path=log, meta={'scene': 'A'})
    trajectory = load_trajectory([log])
    step = np.diff(trajectory.positions_m, axis=0, prepend=trajectory.positions_m[:1])
    return scene, replace(trajectory, headings_rad=np.arctan2(step[:, 1], step[:, 0]))


@pytest.mark.parametrize('fmt', ['mcap', 'ros2'])
def test_a_bag_reads_back_to_the_same_frames_poses_and_metrics(flown, tmp_path, fmt: str) -> None:
    scene, trajectory = flown
    bag = export(trajectory, tmp_path / 'run', fmt, scene)
    again = load_trajectory([bag])
    assert again.robot_ids == trajectory.robot_ids
    np.testing.assert_allclose(again.t_s, trajectory.t_s, rtol=0, atol=1e-9)  # stamps to the nanosecond
    np.testing.assert_array_equal(again.positions_m, trajectory.positions_m)  # doubles, exactly
    np.testing.assert_allclose(again.headings_rad, trajectory.headings_rad, atol=1e-12)
    before, after = analyse(trajectory, scene).metrics, analyse(again, scene).metrics
    assert after.closest == before.closest and before.tube is not None and after.tube is not None
    assert after.tube.passage.passing_time_s == before.tube.passage.passing_time_s is not None
    assert again.source['ignored'] == [
        {'topic': TUBE_TOPIC, 'reason': 'type visualization_msgs/msg/MarkerArray is not read'}
    ]


def test_the_tube_is_drawn_as_line_strips(flown, tmp_path) -> None:
    scene, trajectory = flown
    bag = export(trajectory, tmp_path / 'run', 'mcap', scene)
    with AnyReader([bag]) as reader:
        (connection,) = [c for c in reader.connections if c.topic == TUBE_TOPIC]
        ((_, _, raw),) = list(reader.messages(connections=[connection]))
        markers = reader.deserialize(raw, connection.msgtype).markers
    assert [m.id for m in markers] == [0, 1, 2] and {m.type for m in markers} == {markers[0].LINE_STRIP}
    centre = np.array([[p.x, p.y] for p in markers[0].points])
    np.testing.assert_allclose(centre, scene.tube.center_at(np.linspace(0.0, scene.tube.length_m, len(centre))))
    assert all(m.header.frame_id == 'world' for m in markers)


def test_csv_holds_a_row_per_robot_and_frame_seen(flown, tmp_path) -> None:
    _, trajectory = flown
    path = export(trajectory, tmp_path / 'run.csv', 'csv')
    with path.open(newline='') as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == int(trajectory.present().sum())
    first = rows[trajectory.n_robots + 1]  # the second frame's second robot
    k = trajectory.robot_ids.index(first['robot'])
    assert float(first['t_s']) == trajectory.t_s[1] and float(first['x_m']) == trajectory.positions_m[1, 0, k]
    assert math.isclose(float(first['heading_rad']), trajectory.headings_rad[1, k])


def test_without_headings_a_bag_holds_the_identity_orientation(flown, tmp_path) -> None:
    _, trajectory = flown
    again = load_trajectory([export(replace(trajectory, headings_rad=None), tmp_path / 'run', 'mcap')])
    assert again.headings_rad is not None and np.all(again.headings_rad == 0.0)


def test_what_cannot_be_written_is_refused(flown, tmp_path) -> None:
    _, trajectory = flown
    (tmp_path / 'there').mkdir()
    with pytest.raises(AnalysisError, match='exists; a bag is a new folder'):
        export(trajectory, tmp_path / 'there', 'mcap')
    with pytest.raises(AnalysisError, match="unknown format 'json'; choose from mcap, ros2, csv"):
        export(trajectory, tmp_path / 'x', 'json')
    assert _topic_name('robot_1') == 'robot_1' and _topic_name('3 bots/é') == 'robot_3_bots__'
    assert _topic_names(('a b', 'a_b', 'c')) == ['a_b_0', 'a_b_1', 'c']  # two ids, one name: told apart


def test_a_flight_on_a_map_with_obstacles_exports_and_reads_back_its_passage(tmp_path) -> None:
    """Issue 49: `vtube export --format mcap` of any scene with obstacles was a traceback that left a 43-byte file.
    A Robotarium flight (its start recorded) on the shipped gate map: the bag holds the obstacles' outlines, and
    `analyze` of it times the passage from the flight's start and judges the walls on the bodies, as of the log."""
    from robotarium_exp.analysis.trajectory import RobotSamples, assemble
    from robotarium_exp.scene import load_scene as load_robotarium_scene
    from vtube.cli.tube import map_examples
    from vtube_planning.geometry.from_maps.map_file import generated_scene

    (tmp_path / 'gate.toml').write_text(generated_scene(map_examples()['robotarium_gate'], 'gate.toml')[0])
    scene = load_robotarium_scene(tmp_path / 'gate.toml')
    assert scene.obstacles.outlines()
    l_m = np.linspace(-0.1, scene.tube.length_m + 0.2, 300)[:, None] - np.array([0.0, 0.15])  # two robots along
    centre = scene.tube.center_at(np.clip(l_m.ravel(), 0.0, scene.tube.length_m)).reshape(300, 2, 2)
    stamps = np.arange(300, dtype=np.int64) * 33_000_000
    samples = {f'r{k}': RobotSamples(stamps, centre[:, k]) for k in range(2)}
    start = {'iteration': 800, 'robotarium_time_s': 26.4, 't_s': 0.0}
    source = {'path': 'flight', 'scene': scene.name, 'tube_hash': scene.tube.fingerprint(), 'flight_start': start}
    flight = assemble(samples, source=source)
    bag = export(flight, tmp_path / 'run', 'mcap', scene)
    assert sorted(p.name for p in tmp_path.iterdir()) == ['gate.toml', 'run']  # no partial folder left
    with AnyReader([bag]) as reader:
        (connection,) = [c for c in reader.connections if c.topic == TUBE_TOPIC]
        ((_, _, raw),) = list(reader.messages(connections=[connection]))
        markers = reader.deserialize(raw, connection.msgtype).markers
    assert len(markers) == 3 + len(scene.obstacles.outlines())
    outline = np.array([[p.x, p.y] for p in markers[3].points])
    np.testing.assert_allclose(outline, scene.obstacles.outlines()[0].T)
    before, after = analyse(flight, scene).metrics.tube, analyse(load_trajectory([bag]), scene).metrics.tube
    assert before is not None and after is not None
    assert after.passage.start == before.passage.start and after.passage.start.startswith('start recorded by the')
    assert after.passage.passing_time_s == pytest.approx(before.passage.passing_time_s, abs=1e-9)
    assert after.body_radius_m == before.body_radius_m > 0.0


def test_a_failed_bag_leaves_nothing_behind(flown, tmp_path, monkeypatch) -> None:
    import robotarium_exp.analysis.export as export_module

    _, trajectory = flown

    def broken(trajectory, out, storage, scene) -> None:
        out.mkdir()
        (out / 'half.mcap').write_bytes(b'43 bytes of a bag that never got its messages')
        raise ValueError('too many values to unpack')

    monkeypatch.setattr(export_module, '_write_bag', broken)
    with pytest.raises(ValueError, match='too many values'):
        export(trajectory, tmp_path / 'run', 'mcap')
    assert list(tmp_path.iterdir()) == []
