"""Connections to pose streams: which are read (and why not), how robots are named, rows from real messages."""

from __future__ import annotations

import math
import re
from types import SimpleNamespace

import numpy as np
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from robotarium_exp.analysis.bag_layouts import Poses
from robotarium_exp.analysis.bag_messages import (
    NO_FRAME,
    ODOMETRY,
    POSE_2D,
    POSE_STAMPED,
    STATIC_TF,
    TF_MESSAGE,
    PoseStream,
    Selection,
    handler_for,
)
from tests.support.bags import PERIOD_NS, ROBOTS, START_NS, truth, write_bag

VRPN = re.compile(r'^/vrpn_client_node/(?P<robot>[^/]+)/pose$')


def selection(topics: list[str] | None = None, frame: str = r'^(?P<robot>r\d)$') -> Selection:
    return Selection(topics, [VRPN], re.compile(frame))


def test_a_stream_collects_stamps_and_poses_as_arrays() -> None:
    stream = PoseStream('r1', 'world', '/t', False)
    assert stream.arrays()[0].shape == (0,) and stream.arrays()[1].shape == (0, 3)
    stream = PoseStream('r1', 'world', '/t', False)
    stream.add([])
    stream.add([(1, 5, 0.1, 0.2, 0.0, 0.0, 0.0, 1.0)])
    stream.add([(2, 7, 0.3, 0.4, 0.0, 0.0, 1.0, 0.0)] * 2)  # a half turn about z
    stream.add_poses(Poses(np.arange(5000, dtype=np.int64), np.ones((5000, 2)), np.zeros(5000), 'world'))  # grows
    stamps, values = stream.arrays()
    assert stamps.shape == (5003,) and values.shape == (5003, 3) and stamps.dtype == np.int64
    assert stream.arrays()[0] is stamps  # cut to size once
    np.testing.assert_array_equal(stamps[:3], [1_000_000_005, 2_000_000_007, 2_000_000_007])
    np.testing.assert_allclose(values[:3], [[0.1, 0.2, 0.0], [0.3, 0.4, math.pi], [0.3, 0.4, math.pi]])
    np.testing.assert_array_equal(stamps[3:], np.arange(5000))
    np.testing.assert_array_equal(values[3:], np.c_[np.ones((5000, 2)), np.zeros(5000)])


def test_robots_are_named_by_the_pattern_or_by_the_topic_asked_for() -> None:
    s = selection()
    assert s.robot_of_topic('/vrpn_client_node/alpha/pose') == 'alpha'
    assert s.robot_of_topic('/elsewhere/pose') is None
    asked = selection(['/elsewhere/pose'])
    assert asked.robot_of_topic('/elsewhere/pose') == '/elsewhere/pose'  # no robot group: the topic itself
    assert s.stream('a', 'world', '/t', False) is s.stream('a', 'world', '/t', False) and len(s.candidates) == 1


def test_connections_not_read_are_listed_with_the_reason() -> None:
    s = selection(['/vrpn_client_node/a/pose', '/status'])
    defaults = get_typestore(Stores.ROS2_HUMBLE)
    for topic, msgtype in (
        ('/status', 'std_msgs/msg/String'),
        ('/vrpn_client_node/b/pose', POSE_STAMPED),
    ):
        assert handler_for(SimpleNamespace(topic=topic, msgtype=msgtype), False, defaults, s) is None
    assert s.ignored == [
        {'topic': '/status', 'reason': 'type std_msgs/msg/String is not read'},
        {'topic': '/vrpn_client_node/b/pose', 'reason': 'not among the topics asked for (--topic)'},
    ]
    free = selection()
    assert handler_for(SimpleNamespace(topic='/cmd', msgtype=POSE_2D), False, defaults, free) is None
    assert free.ignored == [{'topic': '/cmd', 'reason': 'does not match the topic pattern(s)'}]
    assert {POSE_STAMPED, ODOMETRY, TF_MESSAGE, POSE_2D} == {
        'geometry_msgs/msg/PoseStamped',
        'nav_msgs/msg/Odometry',
        'tf2_msgs/msg/TFMessage',
        'geometry_msgs/msg/Pose2D',
    }


def feed(path, s: Selection) -> None:
    """Every message of the bag through its connection's handler, in one batch per connection."""
    defaults = get_typestore(Stores.ROS2_HUMBLE)
    with AnyReader([path]) as reader:
        for c in reader.connections:
            handler = handler_for(c, False, defaults, s)
            if handler is not None:
                batch = [(raw, t) for _, t, raw in reader.messages(connections=[c])]
                assert handler(batch) == (0, None)


def test_pose_messages_become_stamps_positions_and_headings(tmp_path) -> None:
    s = selection()
    feed(write_bag(tmp_path / 'p', 'sqlite3', 'pose'), s)
    _, xy, theta = truth()
    assert sorted(s.candidates) == [(r, 'world', f'/vrpn_client_node/{r}/pose') for r in ROBOTS]
    stamps, values = s.candidates['r2', 'world', '/vrpn_client_node/r2/pose'].arrays()
    np.testing.assert_array_equal(stamps, START_NS + np.arange(len(stamps)) * PERIOD_NS)
    np.testing.assert_allclose(values[:, :2], xy[:, :, 1])
    np.testing.assert_allclose(values[:, 2], theta[:, 1], atol=1e-12)


def test_pose_2d_takes_the_bag_time_and_no_frame(tmp_path) -> None:
    s = Selection(None, [re.compile(r'^/(?P<robot>[^/]+)/pose2d$')], re.compile('.*'))
    feed(write_bag(tmp_path / 'p2', 'mcap', 'pose2d'), s)
    stamps, values = s.candidates['r3', NO_FRAME, '/r3/pose2d'].arrays()
    _, _, theta = truth()
    np.testing.assert_array_equal(stamps, START_NS + np.arange(len(stamps)) * PERIOD_NS)  # the bag's time
    np.testing.assert_allclose(values[:, 2], theta[:, 2], atol=1e-12)


def test_tf_frames_are_named_by_the_frame_pattern(tmp_path) -> None:
    s = selection(frame=r'^(?P<robot>r[13])$')
    feed(write_bag(tmp_path / 'tf', 'mcap', 'tf'), s)
    assert sorted(s.candidates) == [('r1', 'world', '/tf'), ('r3', 'world', '/tf')]
    assert s.ignored == [{'topic': '/tf', 'frame': 'r2', 'reason': 'does not match the frame pattern'}]
    assert s.candidates['r1', 'world', '/tf'].tf and STATIC_TF == '/tf_static'
