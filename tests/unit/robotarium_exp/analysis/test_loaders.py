"""Trajectories from testbed folders, our logs and ROS bags; analysis metrics; bad input."""

from __future__ import annotations

import sqlite3

import numpy as np
import pytest
from rosbags.rosbag1 import Writer as Writer1

from robotarium_exp.analysis.loaders import load_trajectory
from robotarium_exp.analysis.report import analyse
from robotarium_exp.errors import AnalysisError
from robotarium_exp.scene import load_scene
from tests.support.bags import KINDS, ROBOTS, START_NS, truth, write_bag


@pytest.mark.parametrize('fmt', ['ros1', 'sqlite3', 'mcap'])
@pytest.mark.parametrize('kind', sorted(KINDS))
def test_bag_round_trip(tmp_path, fmt: str, kind: str) -> None:
    path = write_bag(tmp_path / 'bag', fmt, kind)
    trajectory = load_trajectory([path])
    t, xy, theta = truth()
    assert trajectory.robot_ids == ROBOTS
    np.testing.assert_allclose(trajectory.t_s, t, atol=1e-9)
    np.testing.assert_allclose(trajectory.positions_m, xy, atol=1e-9)
    np.testing.assert_allclose(trajectory.headings_rad, theta, atol=1e-9)
    assert trajectory.gaps == ()


def test_bag_without_type_definitions(tmp_path) -> None:
    path = write_bag(tmp_path / 'old', 'sqlite3', 'pose')
    with sqlite3.connect(next(path.glob('*.db3'))) as con:  # a Humble-era bag: no definitions stored
        con.execute('DELETE FROM message_definitions')
    np.testing.assert_allclose(load_trajectory([path]).positions_m, truth()[1], atol=1e-9)


def test_frame_pattern_selects_robots_on_tf(tmp_path) -> None:
    path = write_bag(tmp_path / 'tf', 'mcap', 'tf')
    trajectory = load_trajectory([path], frame_pattern=r'^(?P<robot>r[12])$')
    assert trajectory.robot_ids == ('r1', 'r2')


def test_bad_input_gives_clear_errors(tmp_path) -> None:
    with pytest.raises(AnalysisError, match='holds no vtube_\\*.npy files'):
        load_trajectory([tmp_path])
    bag = write_bag(tmp_path / 'b', 'sqlite3', 'pose')
    with pytest.raises(AnalysisError, match="topic '/nowhere' is not in"):
        load_trajectory([bag], topics=['/nowhere'])
    fake = tmp_path / 'fake.bag'
    fake.write_bytes(b'not a bag at all')
    with pytest.raises(AnalysisError, match='cannot read .* as a ROS bag'):
        load_trajectory([fake])
    folder = tmp_path / 'returned'
    folder.mkdir()
    np.save(folder / 'vtube_t.npy', np.arange(10) * 0.033)
    poses = np.zeros((10, 3, 2))
    poses[4, 0, 1] = np.nan
    poses[6, 1, 1] = 1e300  # no measurement either
    np.save(folder / 'vtube_poses.npy', poses)
    scene = load_scene('robotarium_trapezoid')
    nan_pose = analyse(load_trajectory([folder]), scene).metrics.to_json()  # left out and counted
    assert [c['non_finite'] for c in nan_pose['coverage']] == [0, 2] and nan_pose['frames'] == 10
    (folder / 'vtube_poses.npy').write_bytes((folder / 'vtube_poses.npy').read_bytes()[:120])  # truncated
    with pytest.raises(AnalysisError, match=r'truncated or corrupt: vtube_poses.npy \('):
        load_trajectory([folder])
    np.save(folder / 'vtube_poses.npy', np.full((10, 3, 2), 'x'))  # strings where numbers belong
    with pytest.raises(AnalysisError, match=r'vtube_poses.npy \(holds <U1 values, not one array of numbers\)'):
        load_trajectory([folder])
    np.save(folder / 'vtube_poses.npy', np.array([{'x': 1}], dtype=object))  # pickled objects: never loaded
    with pytest.raises(AnalysisError, match=r'holds pickled objects, which are never loaded') as raised:
        load_trajectory([folder])
    assert 'allow_pickle' not in str(raised.value)  # no advice to load them
    np.savez(folder / 'archive.npz', poses=poses)
    (folder / 'archive.npz').rename(folder / 'vtube_poses.npy')  # a zip archive under the array's name
    with pytest.raises(AnalysisError, match=r'vtube_poses.npy \(holds an archive of arrays'):
        load_trajectory([folder])
    with pytest.raises(AnalysisError, match='does not exist'):
        load_trajectory([tmp_path / 'missing.csv'])


def test_a_submission_log_folder_reads_like_any_vtube_log(tmp_path) -> None:
    """vtube_meta.json and one vtube_NAME.npy per array: the trajectory log's schema, cut where a save was
    interrupted between two files; another version is named."""
    import json

    t, positions, headings = truth()
    meta = {'format': 'vtube-trajectory', 'version': 2, 'kind': 'robotarium submission', 'scene': 'robotarium_curve'}
    meta |= {'tube_hash': 'abc', 'planned': True, 'n_robots': 3, 'dt_s': 0.02}
    (tmp_path / 'vtube_meta.json').write_text(json.dumps(meta))
    np.save(tmp_path / 'vtube_t_s.npy', t)
    np.save(tmp_path / 'vtube_positions_m.npy', positions[:-5])  # the last save stopped after t_s
    np.save(tmp_path / 'vtube_headings_rad.npy', headings)
    trajectory = load_trajectory([tmp_path])
    assert trajectory.source['kind'] == 'robotarium submission' and trajectory.source['tube_hash'] == 'abc'
    assert len(trajectory.robot_ids) == 3
    np.testing.assert_array_equal(trajectory.positions_m, positions[:-5])
    (tmp_path / 'vtube_meta.json').write_text(json.dumps(meta | {'version': 7}))
    with pytest.raises(AnalysisError, match='of version 7; this vtube reads versions 1 to 2'):
        load_trajectory([tmp_path])
    (tmp_path / 'vtube_meta.json').write_text('{not json')
    with pytest.raises(AnalysisError, match='vtube_meta.json.* is not readable JSON'):
        load_trajectory([tmp_path])


def test_a_recorded_flight_start_is_passed_on_on_the_trajectory_s_clock(tmp_path) -> None:
    """A submission's folder and a `vtube robotarium run` log carry the flight's start (its t_s on the log's clock,
    here 0.25 s after the log's first row); logs without one (earlier submissions, simulations) carry None."""
    import json

    from vtube_planning.log import LogWriter

    t, positions, headings = truth()
    t = t + 1.0  # the log's first row at t = 1.0 s
    start = {'iteration': 412, 'robotarium_time_s': 13.596, 't_s': 1.25}
    meta = {'format': 'vtube-trajectory', 'version': 2, 'kind': 'robotarium submission', 'flight_start': start}
    (tmp_path / 'vtube_meta.json').write_text(json.dumps(meta))
    for name, values in (('t_s', t), ('positions_m', positions), ('headings_rad', headings)):
        np.save(tmp_path / f'vtube_{name}.npy', values)
    expected = start | {'t_s': pytest.approx(0.25, abs=1e-12)}
    assert load_trajectory([tmp_path]).source['flight_start'] == expected
    log = LogWriter(tmp_path / 'run.npz', {'kind': 'robotarium experiment', 'flight_start': start})
    for k in range(t.size):
        log.append(t_s=t[k], positions_m=positions[k], headings_rad=headings[k])
    log.flush(finished=True)
    assert load_trajectory([tmp_path / 'run.npz']).source['flight_start'] == expected
    (tmp_path / 'vtube_meta.json').write_text(json.dumps(meta | {'flight_start': {'iteration': 'many'}}))
    with pytest.raises(AnalysisError, match='vtube_meta.json: the recorded flight start .* is unreadable'):
        load_trajectory([tmp_path])
    (tmp_path / 'vtube_meta.json').write_text(json.dumps({k: v for k, v in meta.items() if k != 'flight_start'}))
    assert load_trajectory([tmp_path]).source['flight_start'] is None


def test_an_unreadable_type_costs_only_its_topic(tmp_path) -> None:
    from rosbags.highlevel import AnyReader, AnyReaderError

    path = write_bag(tmp_path / 'b', 'ros1', 'pose')
    broken = tmp_path / 'broken.bag'
    with Writer1(broken) as writer:  # a driver's own type whose definition no parser reads
        conn = writer.add_connection(
            '/driver/status', 'driver_msgs/msg/Status', msgdef='int32 [[ not a definition', md5sum='0' * 32
        )
        writer.write(conn, START_NS, b'\x00\x00\x00\x00')
    with pytest.raises(AnyReaderError), AnyReader([path, broken]) as reader:  # rosbags alone refuses both bags
        reader.connections  # noqa: B018
    trajectory = load_trajectory([path, broken])
    np.testing.assert_allclose(trajectory.positions_m, truth()[1], atol=1e-9)
    assert trajectory.source['ignored'] == [
        {'topic': '/driver/status', 'reason': 'type driver_msgs/msg/Status is not read'}
    ]


def test_poses_cut_in_the_middle_of_a_save_are_analysed_up_to_the_cut(tmp_path) -> None:
    """Issue 49: the testbed may stop a run at any time; a vtube_poses.npy cut in a save was refused. The whole
    frames before the cut are read (and only those of vtube_t.npy that match), and the cut is reported."""
    folder = tmp_path / 'returned'
    folder.mkdir()
    np.save(folder / 'vtube_t.npy', np.arange(10) * 0.033)
    poses = np.arange(10 * 3 * 2, dtype=float).reshape(10, 3, 2)
    np.save(folder / 'vtube_poses.npy', poses)
    whole = (folder / 'vtube_poses.npy').read_bytes()
    frame = 3 * 2 * 8
    (folder / 'vtube_poses.npy').write_bytes(whole[: len(whole) - 6 * frame + 20])  # 4 whole frames and a piece
    trajectory = load_trajectory([folder])
    assert trajectory.t_s.size == 4
    np.testing.assert_array_equal(trajectory.positions_m[:, :, 1], poses[:4, :2, 1])
    assert trajectory.source['cut'] == ['vtube_poses.npy: cut in a save after 4 whole frames; those are analysed']
    (folder / 'vtube_poses.npy').write_bytes(whole[: len(whole) - 10 * frame + 5])  # not one whole frame
    with pytest.raises(AnalysisError, match='truncated or corrupt: vtube_poses.npy'):
        load_trajectory([folder])
