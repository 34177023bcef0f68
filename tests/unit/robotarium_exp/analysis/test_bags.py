"""Robots from whole bags: samples in integer nanoseconds, headings from quaternions, frames, what is ignored."""

from __future__ import annotations

import numpy as np
import pytest
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

from robotarium_exp.analysis.bags import DEFAULT_FRAME_PATTERN, DEFAULT_TOPIC_PATTERNS, read_bag
from robotarium_exp.errors import AnalysisError
from tests.support.bags import PERIOD_NS, ROBOTS, START_NS, truth, write_bag


def test_samples_stamps_positions_and_headings(tmp_path) -> None:
    path = write_bag(tmp_path / 'b', 'ros1', 'odom')
    contents = read_bag([path])
    t, xy, theta = truth()
    assert sorted(contents.samples) == list(ROBOTS) and contents.world_frame == 'world'
    assert contents.topics == [f'/{r}/odom' for r in ROBOTS] and contents.ignored == []
    for k, robot in enumerate(ROBOTS):
        s = contents.samples[robot]
        assert s.stamps_ns.dtype == np.int64
        np.testing.assert_array_equal(s.stamps_ns, START_NS + np.arange(t.size) * PERIOD_NS)
        np.testing.assert_allclose(s.xy_m, xy[:, :, k], atol=1e-12)
        np.testing.assert_allclose(s.heading_rad, theta[:, k], atol=1e-12)


def test_patterns_and_their_errors(tmp_path) -> None:
    path = write_bag(tmp_path / 'b', 'sqlite3', 'pose')
    assert DEFAULT_FRAME_PATTERN == r'^(?P<robot>.+)$' and len(DEFAULT_TOPIC_PATTERNS) == 4
    with pytest.raises(AnalysisError, match='not a regular expression'):
        read_bag([path], topic_pattern='(?P<robot>')
    with pytest.raises(AnalysisError, match=r"no robot found in .*e\.g\. --topic-pattern '\^/\(\?P<robot>"):
        read_bag([path], topic_pattern=r'^/nothing/(?P<robot>.+)$')
    only = read_bag([path], topic_pattern=r'^/vrpn_client_node/(?P<robot>r[12])/pose$')
    assert sorted(only.samples) == ['r1', 'r2']
    assert {'topic': '/vrpn_client_node/r3/pose', 'reason': 'does not match the topic pattern(s)'} in only.ignored
    with pytest.raises(AnalysisError, match="pose in frame 'world', not the world frame 'map'"):
        read_bag([path], world_frame='map')


def write_frames(path) -> None:
    """/tf: r1 moves in 'world', dock stands still in 'world', r2 moves in 'map'; /tf_static: a camera."""
    ts = get_typestore(Stores.ROS2_HUMBLE)
    T = ts.types
    msgtype = 'tf2_msgs/msg/TFMessage'

    def transform(i: int, child: str, parent: str, x: float):
        t_ns = START_NS + i * PERIOD_NS
        header = T['std_msgs/msg/Header'](
            stamp=T['builtin_interfaces/msg/Time'](sec=t_ns // 10**9, nanosec=t_ns % 10**9), frame_id=parent
        )
        return T['geometry_msgs/msg/TransformStamped'](
            header=header,
            child_frame_id=child,
            transform=T['geometry_msgs/msg/Transform'](
                translation=T['geometry_msgs/msg/Vector3'](x=x, y=0.0, z=0.0),
                rotation=T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=0.0, w=1.0),
            ),
        )

    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as w:
        tf = w.add_connection('/tf', msgtype, typestore=ts)
        static = w.add_connection('/tf_static', msgtype, typestore=ts)
        for i in range(10):
            frames = [transform(i, 'r1', 'world', 0.1 * i), transform(i, 'dock', 'world', 1.0)]
            frames.append(transform(i, 'r2', 'map', -0.1 * i))
            w.write(tf, START_NS + i * PERIOD_NS, ts.serialize_cdr(T[msgtype](transforms=frames), msgtype))
        camera = T[msgtype](transforms=[transform(0, 'camera', 'world', 2.0)])
        w.write(static, START_NS, ts.serialize_cdr(camera, msgtype))


def test_tf_frames_still_static_and_in_another_frame(tmp_path) -> None:
    path = tmp_path / 'frames'
    write_frames(path)
    with pytest.raises(AnalysisError, match=r"different reference frames .*\{'map': \['r2'\], 'world': \['r1'\]\}"):
        read_bag([path])
    contents = read_bag([path], world_frame='world')
    assert sorted(contents.samples) == ['r1'] and contents.world_frame == 'world'
    np.testing.assert_allclose(contents.samples['r1'].xy_m[:, 0], 0.1 * np.arange(10))
    assert {'topic': '/tf', 'frame': 'dock', 'reason': 'does not move'} in contents.ignored
    assert {'topic': '/tf_static', 'frame': 'camera', 'reason': 'static transform'} in contents.ignored
    assert {'topic': '/tf', 'frame': 'r2', 'reason': "pose in frame 'map', not the world frame 'world'"} in (
        contents.ignored
    )
