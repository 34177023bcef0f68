"""A bag connection's messages decoded into pose rows, one stream per candidate robot.

A candidate is one pose topic in one reference frame, or one (child, parent) pair of a /tf topic. Each connection
is decoded with the types its own definition describes (or the default store's, without one), in batches; a batch
that fails is decoded message by message, to keep what can be read and count the rest.
"""

from __future__ import annotations

import math
import re
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.analysis.bag_layouts import Poses, bulk_poses, heading
from robotarium_exp.errors import AnalysisError

POSE_STAMPED = 'geometry_msgs/msg/PoseStamped'
ODOMETRY = 'nav_msgs/msg/Odometry'
TF_MESSAGE = 'tf2_msgs/msg/TFMessage'
POSE_2D = 'geometry_msgs/msg/Pose2D'
SUPPORTED = (POSE_STAMPED, ODOMETRY, TF_MESSAGE, POSE_2D)
STATIC_TF = '/tf_static'
NO_FRAME = ''  # Pose2D has no header: it fits any world frame

Row = tuple[int, int, float, float, float, float, float, float]  # stamp sec, nanosec, x, y, quaternion x, y, z, w
FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
Message = tuple[bytes, int]  # raw bytes and bag time (ns)
Decoded = tuple[list[Any], list[int] | None, int, Exception | None]
"""Messages decoded, their bag times (None when every message of the batch decoded), failures, the first error."""
Decoder = Callable[[list[Message]], Decoded]
Handler = Callable[[list[Message]], tuple[int, Exception | None]]
"""Takes a batch of a connection's messages; gives how many did not decode and the first error."""
BATCH = 1024
"""Messages of one connection decoded together: enough for the bulk reading of one layout
(`bag_layouts`), few enough that decoded objects die young."""


@dataclass
class PoseStream:
    """Samples of one candidate robot: one topic in one reference frame, or one (child, parent) pair of a /tf topic.

    Kept as arrays, so that no message object lives on: stamps (integer nanoseconds) and x, y, heading, in buffers
    that grow by half when full (few large allocations, which the system takes back when freed: thousands of small
    ones would leave the process's memory fragmented at twice the data's size).
    """

    robot: str
    frame: str
    topic: str
    tf: bool
    size: int = 0
    stamps: IntArray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    values: FloatArray = field(default_factory=lambda: np.zeros((0, 3)))

    def add(self, rows: list[Row]) -> None:
        if rows:
            a = np.array(rows, dtype=float)  # seconds (< 2**31) and nanoseconds are exact as floats
            stamps = a[:, 0].astype(np.int64) * 1_000_000_000 + a[:, 1].astype(np.int64)
            self.add_poses(Poses(stamps, a[:, 2:4], heading(a[:, 4], a[:, 5], a[:, 6], a[:, 7]), self.frame))

    def add_poses(self, poses: Poses) -> None:
        end = self.size + poses.stamps_ns.size
        if end > self.stamps.size:
            capacity = max(end, self.stamps.size * 3 // 2, 4096)
            self.stamps = np.concatenate([self.stamps[: self.size], np.zeros(capacity - self.size, dtype=np.int64)])
            self.values = np.concatenate([self.values[: self.size], np.zeros((capacity - self.size, 3))])
        self.stamps[self.size : end] = poses.stamps_ns
        self.values[self.size : end, :2] = poses.xy_m
        self.values[self.size : end, 2] = poses.heading_rad
        self.size = end

    def arrays(self) -> tuple[IntArray, FloatArray]:
        """Stamps (k,) and x, y, heading (k, 3), in the order received (the buffers cut to them once)."""
        if self.stamps.size != self.size:
            self.stamps, self.values = self.stamps[: self.size].copy(), self.values[: self.size].copy()
        return self.stamps, self.values


@dataclass
class Selection:
    """Which connections are read and what they gave: the topics asked for and the naming patterns; the candidate
    streams, what was not read (with the reason) and the type stores built from the bags' definitions."""

    topics: list[str] | None
    topic_res: list[re.Pattern[str]]
    frame_re: re.Pattern[str]
    candidates: dict[tuple[str, str, str], PoseStream] = field(default_factory=dict)
    ignored: list[dict[str, str]] = field(default_factory=list)
    stores: dict[tuple[str, str], Any] = field(default_factory=dict)

    def stream(self, name: str, frame: str, topic: str, tf: bool) -> PoseStream:
        """The candidate stream of robot ``name`` in ``frame`` on ``topic``, made when first asked for."""
        key = (name, frame, topic)
        if key not in self.candidates:
            self.candidates[key] = PoseStream(name, frame, topic, tf)
        return self.candidates[key]

    def robot_of_topic(self, topic: str) -> str | None:
        """The robot a pose topic names (the topic itself when the asked-for topic has no ``robot`` group); None
        when it matches no pattern and was not asked for."""
        match = next((m for m in (r.match(topic) for r in self.topic_res) if m), None)
        if match is None and not self.topics:
            return None
        return match.group('robot') if match and 'robot' in match.groupdict() else topic


def handler_for(c: Any, ros1: bool, defaults: Any, selection: Selection) -> Handler | None:
    """What to do with the messages of connection ``c``, or None (and the reason listed) when it is not read."""
    if c.msgtype not in SUPPORTED:
        selection.ignored.append({'topic': c.topic, 'reason': f'type {c.msgtype} is not read'})
        return None
    if selection.topics and c.topic not in selection.topics:
        selection.ignored.append({'topic': c.topic, 'reason': 'not among the topics asked for (--topic)'})
        return None
    name = c.topic
    if c.msgtype != TF_MESSAGE:
        robot = selection.robot_of_topic(c.topic)
        if robot is None:
            selection.ignored.append({'topic': c.topic, 'reason': 'does not match the topic pattern(s)'})
            return None
        name = robot
    try:
        decode = _deserializer(c, ros1, defaults, selection.stores)
    except Exception as err:  # noqa: BLE001 -- rosbags raises several kinds for a definition it cannot parse
        selection.ignored.append({'topic': c.topic, 'reason': f'type definition of {c.msgtype} cannot be read ({err})'})
        return None
    topic, tf = c.topic, c.msgtype == TF_MESSAGE

    def stream_of(robot: str, frame: str) -> PoseStream:
        return selection.stream(robot, frame, topic, tf)

    if tf:
        return _on_tf(topic, decode, selection, stream_of)
    if c.msgtype == POSE_2D:
        return _on_pose_2d(decode, stream_of, name)
    return _on_poses(decode, stream_of, name, c.msgtype == ODOMETRY, ros1)


def _deserializer(connection: Any, ros1: bool, defaults: Any, stores: dict[tuple[str, str], Any]) -> Decoder:
    """Messages of one connection decoded from its own type definition (or the default types)."""
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
        if key not in stores:
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
            stores[key] = store
        store = stores[key]
    msgtype = connection.msgtype
    deserialize = store.deserialize_ros1 if ros1 else store.deserialize_cdr

    def decode(batch: list[Message]) -> Decoded:
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


def _on_pose_2d(decode: Decoder, stream_of: Callable[[str, str], PoseStream], name: str) -> Handler:
    """Handler of a Pose2D topic: no header, so the bag time and no frame."""

    def on_pose_2d(batch: list[Message]) -> tuple[int, Exception | None]:
        messages, times, failures, problem = decode(batch)
        bag_times = [t for _, t in batch] if times is None else times
        rows = [
            (*divmod(t, 1_000_000_000), m.x, m.y, 0.0, 0.0, math.sin(m.theta / 2), math.cos(m.theta / 2))
            for m, t in zip(messages, bag_times, strict=True)
        ]
        stream_of(name, NO_FRAME).add(rows)
        return failures, problem

    return on_pose_2d


def _on_poses(
    decode: Decoder, stream_of: Callable[[str, str], PoseStream], name: str, odometry: bool, ros1: bool
) -> Handler:
    """Handler of a PoseStamped or Odometry topic: one stream per reference frame (``header.frame_id``); a batch of
    one layout read in bulk (`bulk_poses`), any other decoded."""

    def on_poses(batch: list[Message]) -> tuple[int, Exception | None]:
        if batch:
            head, _, failures, _ = decode(batch[:1])
            if not failures:
                m = head[0]
                at = (m.pose.pose if odometry else m.pose).position
                first = (m.header.stamp.sec, m.header.stamp.nanosec, m.header.frame_id, at.x, at.y)
                bulk = bulk_poses([raw for raw, _ in batch], ros1, odometry, first)
                if bulk is not None:
                    stream_of(name, bulk.frame).add_poses(bulk)
                    return 0, None
        messages, _, failures, problem = decode(batch)
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
            stream_of(name, frames[0]).add(rows)
        else:
            for frame in kinds:
                stream_of(name, frame).add([r for r, f in zip(rows, frames, strict=True) if f == frame])
        return failures, problem

    return on_poses


def _on_tf(topic: str, decode: Decoder, selection: Selection, stream_of: Callable[[str, str], PoseStream]) -> Handler:
    """Handler of a /tf topic: one candidate robot per child frame that matches the frame pattern."""
    names: dict[str, str | None] = {}
    ignored = selection.ignored

    def name_of(child: str) -> str | None:
        if child not in names:
            match = selection.frame_re.match(child)
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
            stream_of(name, parent).add(chunk)
        return failures, problem

    return on_tf
