"""Robot poses from ROS1 bags and ROS2 bag folders (sqlite3 or MCAP) through ``rosbags``' ``AnyReader``.

Supported messages: ``geometry_msgs/PoseStamped``, ``nav_msgs/Odometry``, ``tf2_msgs/TFMessage`` (one robot per
child frame) and ``geometry_msgs/Pose2D`` (no header: the bag time is used). Robots are named by a regular
expression with a group ``robot``, matched against topic names (or, for /tf, child frame ids). The defaults
cover vrpn_client_ros, vrpn_mocap, natnet_ros_cpp and mocap_optitrack (``docs/ecosystem.md`` §1). Time stamps come from
``header.stamp`` when there is one. Bags without embedded type definitions (older rosbag2 sqlite3) are read with
the ROS 2 Humble types, ROS1 bags with the Noetic ones.
"""

from __future__ import annotations

import math
import re
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.analysis.trajectory import Trajectory, on_common_stamps
from robotarium_exp.errors import AnalysisError

POSE_STAMPED = 'geometry_msgs/msg/PoseStamped'
ODOMETRY = 'nav_msgs/msg/Odometry'
TF_MESSAGE = 'tf2_msgs/msg/TFMessage'
POSE_2D = 'geometry_msgs/msg/Pose2D'
SUPPORTED = (POSE_STAMPED, ODOMETRY, TF_MESSAGE, POSE_2D)
DEFAULT_TOPIC_PATTERNS = (
    r'^/vrpn_client_node/(?P<robot>[^/]+)/pose$',  # vrpn_client_ros (ROS 1)
    r'^/vrpn_mocap/(?P<robot>[^/]+)/pose$',  # vrpn_mocap (ROS 2)
    r'^/natnet_ros/(?P<robot>[^/]+)/pose$',  # natnet_ros_cpp
    r'^/(?P<robot>[^/]+)/(?:pose|pose2d|ground_pose|odom)$',  # mocap_optitrack, and most one-topic-per-robot setups
)
DEFAULT_FRAME_PATTERN = r'^(?P<robot>.+)$'


def yaw(q: Any) -> float:
    """Heading of a quaternion (rotation about z)."""
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def stamp_ns(header: Any) -> int:
    """A header's stamp in integer nanoseconds (seconds since 1970 would lose 0.2 us as a float)."""
    return int(header.stamp.sec) * 1_000_000_000 + int(header.stamp.nanosec)


def read_bag(
    paths: list[Path],
    *,
    topic_pattern: str | None = None,
    frame_pattern: str | None = None,
    topics: list[str] | None = None,
) -> Trajectory:
    """Load robot positions from one or more bags (ROS1 ``.bag`` files or one ROS2 bag folder)."""
    from rosbags.highlevel import AnyReader, AnyReaderError
    from rosbags.typesys import Stores, get_typestore

    paths = [Path(p) for p in paths]
    for path in paths:
        if not path.exists():
            msg = f'bag {str(path)!r} does not exist.'
            raise AnalysisError(msg)
    store = Stores.ROS1_NOETIC if all(p.suffix == '.bag' for p in paths) else Stores.ROS2_HUMBLE
    topic_res = [re.compile(topic_pattern)] if topic_pattern else [re.compile(p) for p in DEFAULT_TOPIC_PATTERNS]
    frame_re = re.compile(frame_pattern or DEFAULT_FRAME_PATTERN)
    samples: dict[str, list[tuple[int, float, float, float]]] = defaultdict(list)
    try:
        with AnyReader(paths, default_typestore=get_typestore(store)) as reader:
            available = {c.topic: c.msgtype for c in reader.connections}
            if topics:
                missing = [t for t in topics if t not in available]
                if missing:
                    msg = f'topic {missing[0]!r} is not in {paths[0]}; it has: {sorted(available)}.'
                    raise AnalysisError(msg)
            chosen = [
                c
                for c in reader.connections
                if c.msgtype in SUPPORTED
                and (
                    c.topic in topics if topics else c.msgtype == TF_MESSAGE or any(r.match(c.topic) for r in topic_res)
                )
            ]
            if not chosen:
                msg = (
                    f'no pose topic found in {paths[0]}: it has {sorted(available.items())}; name the topics '
                    '(--topic) or give a pattern with a (?P<robot>...) group (--topic-pattern).'
                )
                raise AnalysisError(msg)
            robot_of = {}
            for c in chosen:
                if c.msgtype != TF_MESSAGE:
                    match = next((m for m in (r.match(c.topic) for r in topic_res) if m), None)
                    robot_of[c.topic] = match.group('robot') if match and 'robot' in match.groupdict() else c.topic
            for connection, t_ns, raw in reader.messages(connections=chosen):
                msg_type = connection.msgtype
                m: Any = reader.deserialize(raw, msg_type)  # a message class of msg_type, known only at run time
                if msg_type == TF_MESSAGE:
                    for tr in m.transforms:
                        match = frame_re.match(tr.child_frame_id)
                        if match:
                            tl = tr.transform.translation
                            samples[match.group('robot')].append(
                                (stamp_ns(tr.header), tl.x, tl.y, yaw(tr.transform.rotation))
                            )
                    continue
                robot = robot_of[connection.topic]
                if msg_type == POSE_2D:
                    samples[robot].append((int(t_ns), m.x, m.y, m.theta))
                else:
                    pose = m.pose.pose if msg_type == ODOMETRY else m.pose
                    samples[robot].append((stamp_ns(m.header), pose.position.x, pose.position.y, yaw(pose.orientation)))
    except AnyReaderError as err:
        msg = f'cannot read {paths[0]} as a ROS bag: {err}. ROS1 bags end in .bag; ROS2 bags are folders.'
        raise AnalysisError(msg) from err
    origin = min((min(r[0] for r in rows) for rows in samples.values()), default=0)
    per_robot = {}
    for robot, rows in samples.items():
        rows.sort()
        stamps = np.array([r[0] for r in rows], dtype=np.int64)
        values = np.array([r[1:] for r in rows], dtype=float)
        keep = np.concatenate([[True], np.diff(stamps) > 0])  # duplicate stamps (e.g. /tf and a pose topic)
        seconds = (stamps[keep] - origin) * 1e-9  # the one conversion of bag nanoseconds to seconds
        per_robot[robot] = (seconds, values[keep, :2], values[keep, 2])
    return on_common_stamps(
        per_robot, source={'kind': 'ros bag', 'path': str(paths[0]), 'topics': sorted({c.topic for c in chosen})}
    )
