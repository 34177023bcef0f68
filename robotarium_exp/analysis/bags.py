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

import math
import re
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

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
FloatArray = NDArray[np.float64]
Message = tuple[bytes, int]  # raw bytes and bag time (ns)
BATCH = 64
"""Messages of one connection decoded together: a list comprehension per batch saves Python's per-message work, and
a batch small enough (a few hundred objects, under the collector's first threshold of 700) dies young; at 128 and
above, the messages outlive collections and loading is 15-40 % slower (benchmarks/analysis_bench.py)."""


@dataclass
class _Poses:
    """Rows of one candidate robot: one topic in one reference frame, or one (child, parent) pair of a /tf topic."""

    robot: str
    frame: str
    topic: str
    tf: bool
    chunks: list[FloatArray] = field(default_factory=list)  # (k, 8) rows: floats, so that no message object lives on

    def add(self, rows: list[Row]) -> None:
        if rows:
            self.chunks.append(np.array(rows, dtype=float))  # seconds (< 2**31) and nanoseconds are exact as floats

    def array(self) -> FloatArray:
        return np.concatenate(self.chunks) if self.chunks else np.zeros((0, 8))


@dataclass
class BagContents:
    """What a bag holds: the robots' samples, and every topic or frame not read, with the reason."""

    samples: dict[str, RobotSamples]
    world_frame: str | None
    topics: list[str]
    ignored: list[dict[str, str]]


def _deserializer(
    connection: Any, ros1: bool, defaults: Any, cache: dict[tuple[str, str], Any]
) -> Callable[[list[Message]], tuple[list[Any], list[int] | None, int, Exception | None]]:
    """Messages of one connection decoded from its own type definition (or the default types): the messages, their
    bag times (None when every message decoded: those of the batch), how many did not and the first error."""
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

    def decode(batch: list[Message]) -> tuple[list[Any], list[int] | None, int, Exception | None]:
        try:
            return [deserialize(raw, msgtype) for raw, _ in batch], None, 0, None  # None: the batch's bag times
        except Exception:  # noqa: BLE001 -- decode one by one, to keep what can be read and count the rest
            messages, times, failures, first = [], [], 0, None
            for raw, t_ns in batch:
                try:
                    messages.append(deserialize(raw, msgtype))
                    times.append(t_ns)
                except Exception as err:  # noqa: BLE001 -- rosbags raises several kinds for a bad message
                    failures, first = failures + 1, first or err
            return messages, times, failures, first

    return decode


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
                batches: dict[int, list[Message]] = {c.id: [] for c in chosen}
                failed: dict[int, list[Any]] = {c.id: [0, None] for c in chosen}
                for connection, t_ns, raw in reader.messages(connections=chosen) if chosen else ():  # (): all
                    batch = batches[connection.id]
                    batch.append((raw, t_ns))
                    if len(batch) == BATCH:
                        _decode(handlers[connection.id], batch, failed[connection.id])
                for c in chosen:
                    _decode(handlers[c.id], batches[c.id], failed[c.id])
                    if failed[c.id][0]:
                        reason = f'{failed[c.id][0]} message(s) could not be decoded ({failed[c.id][1]})'
                        ignored.append({'topic': c.topic, 'reason': reason})
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


def _decode(
    handler: Callable[[list[Message]], tuple[int, Exception | None]], batch: list[Message], failed: list[Any]
) -> None:
    """Hand a batch of messages to its handler and empty it; count what did not decode (and the first error)."""
    failures, problem = handler(batch)
    failed[0] += failures
    failed[1] = failed[1] or problem
    batch.clear()


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
) -> Callable[[list[Message]], tuple[int, Exception | None]] | None:
    """What to do with the messages of connection ``c`` (the count and first error of those that did not decode),
    or None (and the reason listed) when it is not read."""
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
        decode = _deserializer(c, ros1, defaults, cache)
    except Exception as err:  # noqa: BLE001 -- rosbags raises several kinds for a definition it cannot parse
        ignored.append({'topic': c.topic, 'reason': f'type definition of {c.msgtype} cannot be read ({err})'})
        return None

    def poses_of(name: str, frame: str) -> _Poses:
        key = (name, frame, c.topic)
        if key not in candidates:
            candidates[key] = _Poses(name, frame, c.topic, c.msgtype == TF_MESSAGE)
        return candidates[key]

    if c.msgtype == TF_MESSAGE:
        return _on_tf(c.topic, decode, frame_re, poses_of, ignored)
    name = c.topic if robot is None else robot
    odometry = c.msgtype == ODOMETRY

    def on_poses(batch: list[Message]) -> tuple[int, Exception | None]:
        messages, times, failures, problem = decode(batch)
        if c.msgtype == POSE_2D:  # no header: the bag time, no frame
            bag_times = [t for _, t in batch] if times is None else times
            rows = [
                (*divmod(t, 1_000_000_000), m.x, m.y, 0.0, 0.0, math.sin(m.theta / 2), math.cos(m.theta / 2))
                for m, t in zip(messages, bag_times, strict=True)
            ]
            poses_of(name, NO_FRAME).add(rows)
            return failures, problem
        poses = [m.pose.pose for m in messages] if odometry else [m.pose for m in messages]
        stamps = [m.header.stamp for m in messages]
        rows = [
            (
                s.sec,
                s.nanosec,
                p.position.x,
                p.position.y,
                p.orientation.x,
                p.orientation.y,
                p.orientation.z,
                p.orientation.w,
            )
            for s, p in zip(stamps, poses, strict=True)
        ]
        frames = [m.header.frame_id for m in messages]
        kinds = set(frames)
        if len(kinds) == 1:  # almost always
            poses_of(name, frames[0]).add(rows)
        else:
            for frame in kinds:
                poses_of(name, frame).add([r for r, f in zip(rows, frames, strict=True) if f == frame])
        return failures, problem

    return on_poses


def _on_tf(
    topic: str,
    decode: Callable[[list[Message]], tuple[list[Any], list[int] | None, int, Exception | None]],
    frame_re: re.Pattern[str],
    poses_of: Callable[[str, str], _Poses],
    ignored: list[dict[str, str]],
) -> Callable[[list[Message]], tuple[int, Exception | None]]:
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

    def on_tf(batch: list[Message]) -> tuple[int, Exception | None]:
        messages, _, failures, problem = decode(batch)
        rows: dict[tuple[str, str], list[Row]] = defaultdict(list)
        for message in messages:
            for tr in message.transforms:
                name = name_of(tr.child_frame_id)
                if name is not None:
                    tl, q, stamp = tr.transform.translation, tr.transform.rotation, tr.header.stamp
                    row = (stamp.sec, stamp.nanosec, tl.x, tl.y, q.x, q.y, q.z, q.w)
                    rows[name, tr.header.frame_id].append(row)
        for (name, parent), chunk in rows.items():
            poses_of(name, parent).add(chunk)
        return failures, problem

    return on_tf


def _robots(
    candidates: dict[tuple[str, str, str], _Poses], world_frame: str | None, ignored: list[dict[str, str]]
) -> tuple[dict[str, RobotSamples], str | None]:
    """Robots from the candidate pose streams: /tf frames that move, and pose topics, in the world frame."""
    moving = []
    for poses in candidates.values():
        xy = poses.array()[:, 2:4]
        if poses.tf and np.all(xy == xy[0]):
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
    rows: dict[str, list[FloatArray]] = defaultdict(list)
    for poses in moving:
        if poses.frame in (world, NO_FRAME):
            rows[poses.robot].append(poses.array())
        else:
            where = {'topic': poses.topic, 'frame': poses.robot} if poses.tf else {'topic': poses.topic}
            ignored.append({**where, 'reason': f'pose in frame {poses.frame!r}, not the world frame {world!r}'})
    samples = {}
    for robot, parts in rows.items():
        arr = np.concatenate(parts)
        stamps = arr[:, 0].astype(np.int64) * 1_000_000_000 + arr[:, 1].astype(np.int64)
        qx, qy, qz, qw = arr[:, 4], arr[:, 5], arr[:, 6], arr[:, 7]
        heading = np.arctan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
        samples[robot] = RobotSamples(stamps, arr[:, 2:4], heading)
    return samples, world
