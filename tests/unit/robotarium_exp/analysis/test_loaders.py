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


def test_gaps_in_integer_nanoseconds_and_max_gap() -> None:
    from fractions import Fraction

    from robotarium_exp.analysis.trajectory import MaxGap, RobotSamples, assemble

    period = 10_000_000  # 0.01 s
    stamps = np.arange(100, dtype=np.int64) * period
    keep = (stamps < 30 * period) | (stamps >= 32 * period)  # a hole of exactly 3 periods: bridged
    keep &= (stamps < 60 * period) | (stamps > 64 * period)  # a hole of 6 periods: a gap
    xy = np.stack([stamps * 1e-9, stamps * 2e-9], axis=1)
    samples = {'a': RobotSamples(stamps, xy), 'b': RobotSamples(stamps[keep], xy[keep])}
    traj = assemble(samples, source={'path': 'x'})
    assert [(g.robot, round(g.start_s, 9), round(g.end_s, 9)) for g in traj.gaps] == [('b', 0.59, 0.65)]
    np.testing.assert_allclose(traj.positions_m[30:32, :, 1], xy[30:32])  # robot a sets the frames; b on a line
    assert np.isnan(traj.positions_m[60:65, 0, 1]).all() and np.isfinite(traj.positions_m[[59, 65], 0, 1]).all()
    b = traj.coverage[1]
    assert (b.samples, b.frames, b.in_gaps, b.before_first, b.after_last) == (93, 95, 5, 0, 0)
    assert MaxGap.parse('250ms') == MaxGap(Fraction(1, 4), 's') and str(MaxGap.parse('2p')) == '2periods'
    strict = assemble(samples, source={'path': 'x'}, max_gap=MaxGap.parse('0.029s'))
    assert len(strict.gaps) == 2
    with pytest.raises(AnalysisError, match="'3' is not a number with a unit"):
        MaxGap.parse('3')


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
    nan_pose = analyse(load_trajectory([folder]), scene).metrics.to_json()  # a NaN pose is left out and counted
    assert [c['non_finite'] for c in nan_pose['coverage']] == [0, 1] and nan_pose['frames'] == 10
    (folder / 'vtube_poses.npy').write_bytes((folder / 'vtube_poses.npy').read_bytes()[:120])  # truncated
    with pytest.raises(AnalysisError, match=r"truncated or corrupt: \['vtube_poses.npy"):
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


def test_analysis_without_a_tube(tmp_path, capsys) -> None:
    from vtube.cli import main

    path = write_bag(tmp_path / 'b', 'mcap', 'tf')
    assert main(['analyze', str(path), '--out', str(tmp_path / 'a'), '--collision-distance', '0.31']) == 0
    out = capsys.readouterr().out
    assert 'without a tube' in out and 'passing time' not in out
    _, xy, _ = truth()
    gaps = [np.hypot(*(xy[:, :, i] - xy[:, :, j]).T) for i, j in ((0, 1), (0, 2), (1, 2))]
    closest = int(np.argmin([g.min() for g in gaps]))
    assert f'minimum distance {gaps[closest].min():.3f} m' in out
    assert f'{sum(int(g.min() < 0.31) for g in gaps)} pairs closer than 0.310 m' in out
