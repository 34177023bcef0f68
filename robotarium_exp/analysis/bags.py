"""Robot poses from ROS1 bags and ROS2 bags (folders, or bare ``.mcap`` / ``.db3`` files) through ``rosbags``.

Supported messages: ``geometry_msgs/PoseStamped``, ``nav_msgs/Odometry``, ``tf2_msgs/TFMessage`` and
``geometry_msgs/Pose2D`` (no header: the bag time is used). Robots are named by a regular expression with a group
``robot``, matched against topic names (or, for /tf, child frame ids). The defaults cover vrpn_client_ros,
vrpn_mocap, natnet_ros_cpp and mocap_optitrack (``docs/ecosystem.md`` §1). Time stamps come from ``header.stamp``
when there is one, as integer nanoseconds.

What is not a robot is listed, with the reason, never an error: a topic of a type we do not read, or whose type
definition cannot be read; a topic or a /tf frame that does not match the patterns; a frame on ``/tf_static`` or one
that never moves; a pose in another frame than the world frame. The world frame is the reference frame (the /tf
parent, the pose's ``header.frame_id``) of the robots; they must share it, or the user names it
(``world_frame``). Each connection gets the types its own definition describes, so that one unreadable definition
costs only its topic; bags without embedded definitions (older rosbag2 sqlite3) are read with the ROS 2 Humble
types, ROS1 bags with the Noetic ones.
"""

from __future__ import annotations

import re
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.analysis.trajectory import RobotSamples
from robotarium_exp.errors import AnalysisError

POSE_STAMPED = 'geometry_msgs/msg/PoseStamped'
ODOMETRY = 'nav_msgs/msg/Odometry'
TF_MESSAGE = 'tf2_msgs/msg/TFMessage'
POSE_2D = 'geometry_msgs/msg/Pose2D'
SUPPORTED = (POSE_STAMPED, ODOMETRY, TF_MESSAGE, POSE_2D)
STATIC_TF = '/tf_static'
DEFAULT_TOPIC_PATTERNS = (
    r'^/vrpn_client_node/(?P<robot>[^/]+)/pose$',  # vrpn_client_ros (ROS 1)
    r'^/vrpn_mocap/(?P<robot>[^/]+)/pose$',  # vrpn_mocap (ROS 2)
    r'^/natnet_ros/(?P<robot>[^/]+)/pose$',  # natnet_ros_cpp
    r'^/(?P<robot>[^/]+)/(?:pose|pose2d|ground_pose|odom)$',  # mocap_optitrack, and most one-topic-per-robot setups
)
DEFAULT_FRAME_PATTERN = r'^(?P<robot>.+)$'
NO_FRAME = ''  # Pose2D has no header: it fits any world frame

Row = tuple[int, int, float, float, float, float, float, float]  # stamp sec, nanosec, x, y, quaternion x, y, z, w


@dataclass
class _Poses:
    """Rows of one candidate robot: one topic in one reference frame, or one (child, parent) pair of a /tf topic."""

    robot: str
    frame: str
    topic: str
    tf: bool
    rows: list[Row] = field(default_factory=list)


@dataclass
class BagContents:
    """What a bag holds: the robots' samples, and every topic or frame not read, with the reason."""

    samples: dict[str, RobotSamples]
    world_frame: str | None
    topics: list[str]
    ignored: list[dict[str, str]]


def _deserializer(connection: Any, ros1: bool, defaults: Any, cache: dict[tuple[str, str], Any]) -> Callable:
    """A function raw bytes -> message for one connection, from its own type definition (or the default types)."""
    from rosbags.interfaces import MessageDefinitionFormat
    from rosbags.typesys import Stores, get_types_from_idl, get_types_from_msg, get_typestore

    msgdef = connection.msgdef
    if msgdef.format == MessageDefinitionFormat.NONE or not msgdef.data:
        if connection.msgtype not in defaults.types:
            msg = 'the bag has no definition of its type'
            raise AnalysisError(msg)
        store = defaults
    else:
        key = (connection.msgtype, msgdef.data)
        if key not in cache:
            if msgdef.format == MessageDefinitionFormat.MSG:
                types = get_types_from_msg(msgdef.data, connection.msgtype)
            else:  # IDL, possibly several blocks (rosbag2's layout)
                sep = '=' * 80 + '\n'
                blocks = msgdef.data.split(sep)[1:] if msgdef.data.startswith(sep + 'IDL: ') else [msgdef.data]
                types = {}
                for block in blocks:
                    types.update(get_types_from_idl(block.split('\n', 1)[1] if block.startswith('IDL: ') else block))
            store = get_typestore(Stores.EMPTY)
            store.register(types)
            cache[key] = store
        store = cache[key]
    msgtype = connection.msgtype
    deserialize = store.deserialize_ros1 if ros1 else store.deserialize_cdr
    return lambda raw: deserialize(raw, msgtype)


def _open(path: Path) -> tuple[Any, bool]:
    from rosbags.rosbag1 import Reader as Reader1
    from rosbags.rosbag2 import Reader as Reader2

    ros1 = path.suffix == '.bag'
    return (Reader1(path) if ros1 else Reader2(path)), ros1


def read_bag(
    paths: list[Path],
    *,
    topic_pattern: str | None = None,
    frame_pattern: str | None = None,
    topics: list[str] | None = None,
    world_frame: str | None = None,
) -> BagContents:
    """Robot samples from ROS1 ``.bag`` files, or ROS2 bags (a folder with ``metadata.yaml``, or storage files).

    Parameters
    ----------
    topic_pattern, frame_pattern
        Regular expressions with a group ``robot`` for pose topics and /tf child frames (defaults: module doc).
    topics
        Read only these topics (pose topics are then named by ``topic_pattern``, or by the topic itself).
    world_frame
        The reference frame of the robots; poses in any other frame are ignored. None: the one the robots share.
    """
    from rosbags.rosbag1 import ReaderError as ReaderError1
    from rosbags.rosbag2 import ReaderError as ReaderError2
    from rosbags.typesys import Stores, get_typestore

    try:
        topic_res = [re.compile(p) for p in ([topic_pattern] if topic_pattern else DEFAULT_TOPIC_PATTERNS)]
        frame_re = re.compile(frame_pattern or DEFAULT_FRAME_PATTERN)
    except re.error as err:
        msg = f'the topic or frame pattern is not a regular expression: {err}.'
        raise AnalysisError(msg) from err
    candidates: dict[tuple[str, str, str], _Poses] = {}
    ignored: list[dict[str, str]] = []
    read_topics: set[str] = set()
    available: dict[str, str] = {}
    cache: dict[tuple[str, str], Any] = {}
    for path in paths:
        try:
            reader, ros1 = _open(path)
            with reader:
                defaults = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
                handlers = {}
                for c in reader.connections:
                    available[c.topic] = c.msgtype
                    handler = _handler(c, ros1, defaults, cache, topics, topic_res, frame_re, candidates, ignored)
                    if handler is not None:
                        handlers[c.id] = handler
                        read_topics.add(c.topic)
                chosen = [c for c in reader.connections if c.id in handlers]
                failed: dict[int, list[Any]] = {}
                for connection, t_ns, raw in reader.messages(connections=chosen) if chosen else ():  # (): all
                    try:
                        handlers[connection.id](raw, t_ns)
                    except Exception as err:  # noqa: BLE001 -- a message that does not decode costs its topic only
                        failed.setdefault(connection.id, [connection.topic, 0, err])[1] += 1
                for topic, count, problem in failed.values():
                    ignored.append({'topic': topic, 'reason': f'{count} message(s) could not be decoded ({problem})'})
        except (ReaderError1, ReaderError2, OSError, KeyError, ValueError) as err:
            msg = (
                f'cannot read {path} as a ROS bag: {err}. ROS1 bags are .bag files; ROS2 bags are folders with '
                'metadata.yaml, or .mcap / .db3 files.'
            )
            raise AnalysisError(msg) from err
    if topics:
        missing = [t for t in topics if t not in available]
        if missing:
            msg = f'topic {missing[0]!r} is not in {paths[0]}; it has: {sorted(available)}.'
            raise AnalysisError(msg)
    samples, world = _robots(candidates, world_frame, ignored)
    ignored = [dict(entry) for entry in dict.fromkeys(tuple(i.items()) for i in ignored)]  # each once, in order
    if not samples:
        poses = sorted(t for t, m in available.items() if m in SUPPORTED and m != TF_MESSAGE)
        hint = f"; e.g. --topic-pattern '{_pattern_for(poses[0])}'" if poses else ''
        msg = (
            f'no robot found in {paths[0]}: it has {sorted(available.items())}; ignored: '
            f'{[" ".join(i.values()) for i in ignored][:8]}. Name the topics (--topic), give a pattern with a '
            f'(?P<robot>...) group (--topic-pattern, --frame-pattern) or the world frame (--world-frame){hint}.'
        )
        raise AnalysisError(msg)
    return BagContents(samples, world, sorted(read_topics), ignored)


def _pattern_for(topic: str) -> str:
    """A topic pattern that names a robot by the first part of ``topic``."""
    parts = topic.split('/')
    return (
        '^/(?P<robot>[^/]+)/' + '/'.join(re.escape(p) for p in parts[2:]) + '$'
        if len(parts) > 2
        else '^/(?P<robot>.+)$'
    )


def _handler(
    c: Any,
    ros1: bool,
    defaults: Any,
    cache: dict[tuple[str, str], Any],
    topics: list[str] | None,
    topic_res: list[re.Pattern[str]],
    frame_re: re.Pattern[str],
    candidates: dict[tuple[str, str, str], _Poses],
    ignored: list[dict[str, str]],
) -> Callable[[bytes, int], None] | None:
    """What to do with each message of connection ``c``, or None (and the reason listed) when it is not read."""
    if c.msgtype not in SUPPORTED:
        ignored.append({'topic': c.topic, 'reason': f'type {c.msgtype} is not read'})
        return None
    if topics and c.topic not in topics:
        ignored.append({'topic': c.topic, 'reason': 'not among the topics asked for (--topic)'})
        return None
    robot = None
    if c.msgtype != TF_MESSAGE:
        match = next((m for m in (r.match(c.topic) for r in topic_res) if m), None)
        if match is None and not topics:
            ignored.append({'topic': c.topic, 'reason': 'does not match the topic pattern(s)'})
            return None
        robot = match.group('robot') if match and 'robot' in match.groupdict() else c.topic
    try:
        deserialize = _deserializer(c, ros1, defaults, cache)
    except Exception as err:  # noqa: BLE001 -- rosbags raises several kinds for a definition it cannot parse
        ignored.append({'topic': c.topic, 'reason': f'type definition of {c.msgtype} cannot be read ({err})'})
        return None

    def poses_of(name: str, frame: str) -> list[Row]:
        key = (name, frame, c.topic)
        if key not in candidates:
            candidates[key] = _Poses(name, frame, c.topic, c.msgtype == TF_MESSAGE)
        return candidates[key].rows

    if c.msgtype == TF_MESSAGE:
        return _on_tf(c.topic, deserialize, frame_re, poses_of, ignored)
    name = c.topic if robot is None else robot
    if c.msgtype == POSE_2D:
        rows_2d = poses_of(name, NO_FRAME)

        def on_pose_2d(raw: bytes, t_ns: int) -> None:
            m = deserialize(raw)
            sec, nanosec = divmod(int(t_ns), 1_000_000_000)
            rows_2d.append((sec, nanosec, m.x, m.y, 0.0, 0.0, float(np.sin(m.theta / 2)), float(np.cos(m.theta / 2))))

        return on_pose_2d
    odometry = c.msgtype == ODOMETRY
    by_frame: dict[str, list[Row]] = {}

    def on_pose(raw: bytes, t_ns: int) -> None:
        m = deserialize(raw)
        h = m.header
        pose = m.pose.pose if odometry else m.pose
        p, q = pose.position, pose.orientation
        rows = by_frame.get(h.frame_id)
        if rows is None:
            rows = by_frame[h.frame_id] = poses_of(name, h.frame_id)
        rows.append((h.stamp.sec, h.stamp.nanosec, p.x, p.y, q.x, q.y, q.z, q.w))

    return on_pose


def _on_tf(
    topic: str,
    deserialize: Callable[[bytes], Any],
    frame_re: re.Pattern[str],
    poses_of: Callable[[str, str], list[Row]],
    ignored: list[dict[str, str]],
) -> Callable[[bytes, int], None]:
    """Handler of a /tf topic: one candidate robot per child frame that matches the frame pattern."""
    names: dict[str, str | None] = {}

    def name_of(child: str) -> str | None:
        if child not in names:
            match = frame_re.match(child)
            names[child] = match.group('robot') if match and 'robot' in match.groupdict() else None
            if topic == STATIC_TF:
                ignored.append({'topic': topic, 'frame': child, 'reason': 'static transform'})
                names[child] = None
            elif names[child] is None:
                ignored.append({'topic': topic, 'frame': child, 'reason': 'does not match the frame pattern'})
        return names[child]

    def on_tf(raw: bytes, t_ns: int) -> None:
        for tr in deserialize(raw).transforms:
            name = name_of(tr.child_frame_id)
            if name is not None:
                tl, q = tr.transform.translation, tr.transform.rotation
                stamp = tr.header.stamp
                poses_of(name, tr.header.frame_id).append((stamp.sec, stamp.nanosec, tl.x, tl.y, q.x, q.y, q.z, q.w))

    return on_tf


def _robots(
    candidates: dict[tuple[str, str, str], _Poses], world_frame: str | None, ignored: list[dict[str, str]]
) -> tuple[dict[str, RobotSamples], str | None]:
    """Robots from the candidate pose streams: /tf frames that move, and pose topics, in the world frame."""
    moving = []
    for poses in candidates.values():
        if poses.tf and len({r[2:4] for r in poses.rows}) == 1:
            ignored.append({'topic': poses.topic, 'frame': poses.robot, 'reason': 'does not move'})
        else:
            moving.append(poses)
    frames = sorted({p.frame for p in moving} - {NO_FRAME})
    if world_frame is None and len(frames) > 1:
        by = {f: sorted({p.robot for p in moving if p.frame == f}) for f in frames}
        msg = (
            f'the robots have different reference frames (frame: robots): {by}; name the world frame, e.g. '
            f'--world-frame {frames[0]}; the others are then ignored.'
        )
        raise AnalysisError(msg)
    world = world_frame if world_frame is not None else (frames[0] if frames else None)
    rows: dict[str, list[Row]] = defaultdict(list)
    for poses in moving:
        if poses.frame in (world, NO_FRAME):
            rows[poses.robot].extend(poses.rows)
        else:
            where = {'topic': poses.topic, 'frame': poses.robot} if poses.tf else {'topic': poses.topic}
            ignored.append({**where, 'reason': f'pose in frame {poses.frame!r}, not the world frame {world!r}'})
    samples = {}
    for robot, data in rows.items():
        arr = np.asarray(data, dtype=float)  # seconds (< 2**31) and nanoseconds are exact as floats
        stamps = arr[:, 0].astype(np.int64) * 1_000_000_000 + arr[:, 1].astype(np.int64)
        qx, qy, qz, qw = arr[:, 4], arr[:, 5], arr[:, 6], arr[:, 7]
        heading = np.arctan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
        samples[robot] = RobotSamples(stamps, arr[:, 2:4], heading)
    return samples, world
