"""Trajectories from testbed folders, our logs and ROS bags; analysis metrics; bad input."""

from __future__ import annotations

import sqlite3
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag1 import Writer as Writer1
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Writer2
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from robotarium_exp.analysis.loaders import load_trajectory
from robotarium_exp.analysis.report import analyse
from robotarium_exp.errors import AnalysisError
from vtube_planning import load_scene

ROOT = Path(__file__).resolve().parents[2]
ROBOTS = ('r1', 'r2', 'r3')
STEPS, PERIOD_NS, START_NS = 120, 20_000_000, 1_700_000_000_000_000_000


def truth() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    t = np.arange(STEPS) * PERIOD_NS * 1e-9
    k = np.arange(len(ROBOTS))[None, :]
    x = -1.0 + 0.1 * t[:, None] + 0.3 * k
    y = 0.2 * np.sin(t[:, None] + k)
    theta = np.angle(np.exp(1j * (0.5 * t[:, None] + k)))
    return t, np.stack([x, y], axis=1), theta


def make_messages(ts, ros1: bool):
    T = ts.types

    def header(i: int):
        stamp = T['builtin_interfaces/msg/Time'](
            sec=(START_NS + i * PERIOD_NS) // 10**9, nanosec=(START_NS + i * PERIOD_NS) % 10**9
        )
        if ros1:
            return T['std_msgs/msg/Header'](seq=i, stamp=stamp, frame_id='world')
        return T['std_msgs/msg/Header'](stamp=stamp, frame_id='world')

    def pose(x: float, y: float, theta: float):
        return T['geometry_msgs/msg/Pose'](
            position=T['geometry_msgs/msg/Point'](x=x, y=y, z=0.0),
            orientation=T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=np.sin(theta / 2), w=np.cos(theta / 2)),
        )

    def pose_stamped(i, x, y, th):
        return T['geometry_msgs/msg/PoseStamped'](header=header(i), pose=pose(x, y, th))

    def odometry(i, x, y, th):
        cov = np.zeros(36)
        twist = T['geometry_msgs/msg/Twist'](
            linear=T['geometry_msgs/msg/Vector3'](x=0.0, y=0.0, z=0.0),
            angular=T['geometry_msgs/msg/Vector3'](x=0.0, y=0.0, z=0.0),
        )
        return T['nav_msgs/msg/Odometry'](
            header=header(i),
            child_frame_id='base',
            pose=T['geometry_msgs/msg/PoseWithCovariance'](pose=pose(x, y, th), covariance=cov),
            twist=T['geometry_msgs/msg/TwistWithCovariance'](twist=twist, covariance=cov),
        )

    def pose_2d(i, x, y, th):
        return T['geometry_msgs/msg/Pose2D'](x=x, y=y, theta=th)

    def tf(i, xs, ys, ths):
        transforms = [
            T['geometry_msgs/msg/TransformStamped'](
                header=header(i),
                child_frame_id=name,
                transform=T['geometry_msgs/msg/Transform'](
                    translation=T['geometry_msgs/msg/Vector3'](x=x, y=y, z=0.0),
                    rotation=T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=np.sin(th / 2), w=np.cos(th / 2)),
                ),
            )
            for name, x, y, th in zip(ROBOTS, xs, ys, ths, strict=True)
        ]
        return T['tf2_msgs/msg/TFMessage'](transforms=transforms)

    return pose_stamped, odometry, pose_2d, tf


KINDS = {
    'pose': ('geometry_msgs/msg/PoseStamped', '/vrpn_client_node/{}/pose'),
    'odom': ('nav_msgs/msg/Odometry', '/{}/odom'),
    'pose2d': ('geometry_msgs/msg/Pose2D', '/{}/pose2d'),
    'tf': ('tf2_msgs/msg/TFMessage', '/tf'),
}


def write_bag(path: Path, fmt: str, kind: str) -> Path:
    ros1 = fmt == 'ros1'
    ts = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    if ros1 and 'tf2_msgs/msg/TFMessage' not in ts.types:  # docs/ecosystem.md: the Noetic store lacks it
        ts.register(get_types_from_msg('geometry_msgs/TransformStamped[] transforms', 'tf2_msgs/msg/TFMessage'))
    msgtype, topic = KINDS[kind]
    builders = dict(zip(('pose', 'odom', 'pose2d', 'tf'), make_messages(ts, ros1), strict=True))
    serialize = ts.serialize_ros1 if ros1 else ts.serialize_cdr
    _, xy, theta = truth()
    if ros1:
        path = path.with_suffix('.bag')
        writer = Writer1(path)
    else:
        writer = Writer2(path, version=9, storage_plugin=StoragePlugin.MCAP if fmt == 'mcap' else StoragePlugin.SQLITE3)
    with writer as w:
        conns = {}
        for i in range(STEPS):
            t_ns = START_NS + i * PERIOD_NS
            if kind == 'tf':
                if 'tf' not in conns:
                    conns['tf'] = w.add_connection('/tf', msgtype, typestore=ts)
                w.write(conns['tf'], t_ns, serialize(builders['tf'](i, xy[i, 0], xy[i, 1], theta[i]), msgtype))
                continue
            for k, robot in enumerate(ROBOTS):
                if robot not in conns:
                    conns[robot] = w.add_connection(topic.format(robot), msgtype, typestore=ts)
                msg = builders[kind](i, xy[i, 0, k], xy[i, 1, k], theta[i, k])
                w.write(conns[robot], t_ns, serialize(msg, msgtype))
    return path


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


def test_gaps_are_reported_not_interpolated() -> None:
    from robotarium_exp.analysis.trajectory import on_common_stamps

    t = np.arange(100) * 0.01
    keep = (t < 0.3) | (t > 0.5)
    xy = np.stack([t, t], axis=1)
    traj = on_common_stamps({'a': (t, xy, None), 'b': (t[keep], xy[keep], None)}, source={'path': 'x'})
    assert len(traj.gaps) == 1 and traj.gaps[0].robot == 'b'
    assert np.isnan(traj.positions_m[(traj.t_s > 0.3) & (traj.t_s < 0.5), 0, 1]).all()
    assert traj.complete_frames().sum() < t.size


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
    from_files = analyse(load_trajectory([tmp_path]), scene)
    from_log = analyse(load_trajectory([tmp_path / 'sim.npz']), scene)
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
    strict = analyse(load_trajectory([tmp_path]), scene, collision_distance_m=1.0)  # a chosen, larger radius
    assert strict['collision_distance_m'] == 1.0 and strict['collision_pairs'] > 0


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
    np.save(folder / 'vtube_poses.npy', poses)
    scene = load_scene('robotarium_trapezoid')
    assert analyse(load_trajectory([folder]), scene)['dropped_frames'] == 1  # NaN poses are dropped and counted
    (folder / 'vtube_poses.npy').write_bytes((folder / 'vtube_poses.npy').read_bytes()[:120])  # truncated
    with pytest.raises(AnalysisError, match=r"truncated or corrupt: \['vtube_poses.npy"):
        load_trajectory([folder])
    with pytest.raises(AnalysisError, match='does not exist'):
        load_trajectory([tmp_path / 'missing.csv'])
