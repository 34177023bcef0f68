"""Tiny synthetic ROS bags (ROS 1, ROS 2 sqlite3 and MCAP) of three robots on known paths, written with rosbags."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from rosbags.rosbag1 import Writer as Writer1
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Writer2
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

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
