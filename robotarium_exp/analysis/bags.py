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
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.analysis.bag_messages import (
    BATCH,
    NO_FRAME,
    SUPPORTED,
    TF_MESSAGE,
    Handler,
    Message,
    PoseStream,
    Selection,
    handler_for,
)
from robotarium_exp.analysis.trajectory import RobotSamples, check_time
from robotarium_exp.errors import AnalysisError

DEFAULT_TOPIC_PATTERNS = (
    r'^/vrpn_client_node/(?P<robot>[^/]+)/pose$',  # vrpn_client_ros (ROS 1)
    r'^/vrpn_mocap/(?P<robot>[^/]+)/pose$',  # vrpn_mocap (ROS 2)
    r'^/natnet_ros/(?P<robot>[^/]+)/pose$',  # natnet_ros_cpp
    r'^/(?P<robot>[^/]+)/(?:pose|pose2d|ground_pose|odom)$',  # mocap_optitrack, and most one-topic-per-robot setups
)
DEFAULT_FRAME_PATTERN = r'^(?P<robot>.+)$'


@dataclass
class BagContents:
    """What a bag holds: the robots' samples, every topic or frame not read, with the reason, and its
    ``custom_data`` (ROS2 bags' ``metadata.yaml``; empty for others)."""

    samples: dict[str, RobotSamples]
    world_frame: str | None
    topics: list[str]
    ignored: list[dict[str, str]]
    custom: dict[str, str] = field(default_factory=dict)


@dataclass
class _Seen:
    """Every connection's topic and type, the topics read, and the ROS2 bags' ``custom_data``, over the bags read
    so far."""

    available: dict[str, str] = field(default_factory=dict)
    read_topics: set[str] = field(default_factory=set)
    custom: dict[str, str] = field(default_factory=dict)


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
    try:
        topic_res = [re.compile(p) for p in ([topic_pattern] if topic_pattern else DEFAULT_TOPIC_PATTERNS)]
        frame_re = re.compile(frame_pattern or DEFAULT_FRAME_PATTERN)
    except re.error as err:
        msg = f'the topic or frame pattern is not a regular expression: {err}.'
        raise AnalysisError(msg) from err
    selection = Selection(topics, topic_res, frame_re)
    seen = _Seen()
    for path in paths:
        _read_one(path, selection, seen)
    if topics:
        missing = [t for t in topics if t not in seen.available]
        if missing:
            msg = f'topic {missing[0]!r} is not in {paths[0]}; it has: {sorted(seen.available)}.'
            raise AnalysisError(msg)
    samples, world = _robots(selection.candidates, world_frame, selection.ignored)
    ignored = [dict(entry) for entry in dict.fromkeys(tuple(i.items()) for i in selection.ignored)]  # each once
    if not samples:
        poses = sorted(t for t, m in seen.available.items() if m in SUPPORTED and m != TF_MESSAGE)
        hint = f"; e.g. --topic-pattern '{_pattern_for(poses[0])}'" if poses else ''
        msg = (
            f'no robot found in {paths[0]}: it has {sorted(seen.available.items())}; ignored: '
            f'{[" ".join(i.values()) for i in ignored][:8]}. Name the topics (--topic), give a pattern with a '
            f'(?P<robot>...) group (--topic-pattern, --frame-pattern) or the world frame (--world-frame){hint}.'
        )
        raise AnalysisError(msg)
    return BagContents(samples, world, sorted(seen.read_topics), ignored, seen.custom)


def _read_one(path: Path, selection: Selection, seen: _Seen) -> None:
    """Read one bag's connections into ``selection`` (see [`read_bag`][robotarium_exp.analysis.bags.read_bag])."""
    from rosbags.rosbag1 import ReaderError as ReaderError1
    from rosbags.rosbag2 import ReaderError as ReaderError2
    from rosbags.typesys import Stores, get_typestore

    try:
        reader, ros1 = _open(path)
        with reader:
            defaults = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
            seen.custom.update({} if ros1 else _custom_data(reader))
            handlers = {}
            for c in reader.connections:
                seen.available[c.topic] = c.msgtype
                handler = handler_for(c, ros1, defaults, selection)
                if handler is not None:
                    handlers[c.id] = handler
                    seen.read_topics.add(c.topic)
            _feed(reader, handlers, selection.ignored)
    except (ReaderError1, ReaderError2, OSError, KeyError, ValueError) as err:
        msg = (
            f'cannot read {path} as a ROS bag: {err}. ROS1 bags are .bag files; ROS2 bags are folders with '
            'metadata.yaml, or .mcap / .db3 files.'
        )
        raise AnalysisError(msg) from err


def _custom_data(reader: Any) -> dict[str, str]:
    """A ROS2 bag's ``custom_data`` (``metadata.yaml``; a folder's reader keeps it with its storage's metadata)."""
    holder = getattr(reader, 'storage', reader)
    custom = getattr(getattr(holder, 'metadata', None), 'custom', None)
    return {str(k): str(v) for k, v in custom.items()} if isinstance(custom, dict) else {}


def _open(path: Path) -> tuple[Any, bool]:
    from rosbags.rosbag1 import Reader as Reader1
    from rosbags.rosbag2 import Reader as Reader2

    ros1 = path.suffix == '.bag'
    return (Reader1(path) if ros1 else Reader2(path)), ros1


def _feed(reader: Any, handlers: dict[int, Handler], ignored: list[dict[str, str]]) -> None:
    """The messages of the connections with a handler, in batches of `BATCH` per connection; what did not
    decode is listed with its topic."""
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


def _decode(handler: Handler, batch: list[Message], failed: list[Any]) -> None:
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


def _robots(
    candidates: dict[tuple[str, str, str], PoseStream], world_frame: str | None, ignored: list[dict[str, str]]
) -> tuple[dict[str, RobotSamples], str | None]:
    """Robots from the candidate pose streams: /tf frames that move, and pose topics, in the world frame."""
    moving = []
    for poses in candidates.values():
        xy = poses.arrays()[1][:, :2]
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
    streams: dict[str, list[PoseStream]] = defaultdict(list)
    for poses in moving:
        if poses.frame in (world, NO_FRAME):
            streams[poses.robot].append(poses)
        else:
            where = {'topic': poses.topic, 'frame': poses.robot} if poses.tf else {'topic': poses.topic}
            ignored.append({**where, 'reason': f'pose in frame {poses.frame!r}, not the world frame {world!r}'})
    return {robot: _samples(robot, parts) for robot, parts in streams.items()}, world


def _samples(robot: str, streams: list[PoseStream]) -> RobotSamples:
    """One robot's samples from its streams: each must be in time (`check_time`); several (a robot on two
    topics) are merged by stamp."""
    for stream in streams:
        check_time(robot, stream.arrays()[0])
    stamps, values = streams[0].arrays()
    if len(streams) > 1:
        stamps, values = (np.concatenate(a) for a in zip(*(s.arrays() for s in streams), strict=True))
        order = np.argsort(stamps, kind='stable')
        stamps, values = stamps[order], values[order]
    return RobotSamples(stamps, values[:, :2], values[:, 2])
