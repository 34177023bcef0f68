"""Pose messages read in bulk: the same stamps, positions and headings as rosbags' own deserializers (the oracle),
for ROS 1 and CDR, PoseStamped and Odometry, frame names of every length; batches of another layout refused."""

from __future__ import annotations

import numpy as np
import pytest
from rosbags.typesys import Stores, get_typestore

from robotarium_exp.analysis.bag_layouts import bulk_poses, heading

POSE_STAMPED, ODOMETRY = 'geometry_msgs/msg/PoseStamped', 'nav_msgs/msg/Odometry'


def messages(ros1: bool, odometry: bool, frame: str, child: str, k: int, seed: int) -> list[bytes]:
    """``k`` random messages serialized by rosbags."""
    ts = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    T = ts.types
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(k):
        stamp = T['builtin_interfaces/msg/Time'](sec=int(rng.integers(0, 2**31)), nanosec=int(rng.integers(0, 10**9)))
        header = (
            T['std_msgs/msg/Header'](seq=int(rng.integers(0, 2**32)), stamp=stamp, frame_id=frame)
            if ros1
            else T['std_msgs/msg/Header'](stamp=stamp, frame_id=frame)
        )
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        pose = T['geometry_msgs/msg/Pose'](
            position=T['geometry_msgs/msg/Point'](*rng.normal(size=3)),
            orientation=T['geometry_msgs/msg/Quaternion'](*q),
        )
        if odometry:
            vec = T['geometry_msgs/msg/Vector3']
            twist = T['geometry_msgs/msg/Twist'](linear=vec(*rng.normal(size=3)), angular=vec(*rng.normal(size=3)))
            msg = T['nav_msgs/msg/Odometry'](
                header=header,
                child_frame_id=child,
                pose=T['geometry_msgs/msg/PoseWithCovariance'](pose=pose, covariance=rng.normal(size=36)),
                twist=T['geometry_msgs/msg/TwistWithCovariance'](twist=twist, covariance=rng.normal(size=36)),
            )
        else:
            msg = T['geometry_msgs/msg/PoseStamped'](header=header, pose=pose)
        typename = ODOMETRY if odometry else POSE_STAMPED
        out.append(bytes(ts.serialize_ros1(msg, typename) if ros1 else ts.serialize_cdr(msg, typename)))
    return out


def decoded(raws: list[bytes], ros1: bool, odometry: bool) -> list:
    ts = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    typename = ODOMETRY if odometry else POSE_STAMPED
    return [ts.deserialize_ros1(r, typename) if ros1 else ts.deserialize_cdr(r, typename) for r in raws]


def first_of(message, odometry: bool) -> tuple:
    at = (message.pose.pose if odometry else message.pose).position
    return message.header.stamp.sec, message.header.stamp.nanosec, message.header.frame_id, at.x, at.y


@pytest.mark.parametrize('ros1', [True, False])
@pytest.mark.parametrize('odometry', [False, True])
def test_bulk_reading_gives_what_rosbags_decodes(ros1: bool, odometry: bool) -> None:
    for seed, (frame, child) in enumerate([('', ''), ('w', 'b'), ('world', 'base_link'), ('map_é' * 3, 'x' * 7)]):
        raws = messages(ros1, odometry, frame, child, 40, seed)
        truth = decoded(raws, ros1, odometry)
        poses = bulk_poses(raws, ros1, odometry, first_of(truth[0], odometry))
        assert poses is not None and poses.frame == frame
        pose = [m.pose.pose if odometry else m.pose for m in truth]
        np.testing.assert_array_equal(
            poses.stamps_ns, [m.header.stamp.sec * 1_000_000_000 + m.header.stamp.nanosec for m in truth]
        )
        np.testing.assert_array_equal(poses.xy_m, [[p.position.x, p.position.y] for p in pose])
        q = np.array([[p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w] for p in pose])
        np.testing.assert_allclose(poses.heading_rad, heading(*q.T))


def test_heading_is_the_yaw_of_the_quaternion() -> None:
    yaw = np.linspace(-3.0, 3.0, 13)
    np.testing.assert_allclose(heading(0 * yaw, 0 * yaw, np.sin(yaw / 2), np.cos(yaw / 2)), yaw, atol=1e-12)
    # a roll of the body about its x axis (the yaw's quaternion times the roll's) leaves its heading as it is
    roll = np.pi / 5
    qx, qw = np.sin(roll / 2) * np.cos(yaw / 2), np.cos(roll / 2) * np.cos(yaw / 2)
    qy, qz = np.sin(roll / 2) * np.sin(yaw / 2), np.cos(roll / 2) * np.sin(yaw / 2)
    np.testing.assert_allclose(heading(qx, qy, qz, qw), yaw, atol=1e-12)


@pytest.mark.parametrize('ros1', [True, False])
def test_batches_of_another_layout_are_left_to_rosbags(ros1: bool) -> None:
    raws = messages(ros1, False, 'world', '', 8, 1)
    first = first_of(decoded(raws[:1], ros1, False)[0], False)
    assert bulk_poses(raws, ros1, False, first) is not None
    same_length = messages(ros1, False, 'wxrld', '', 1, 2)
    assert bulk_poses([*raws, *same_length], ros1, False, first) is None  # another frame name, same length
    assert bulk_poses([*raws, *messages(ros1, False, 'map', '', 1, 3)], ros1, False, first) is None  # length
    assert bulk_poses(raws, ros1, False, (*first[:4], first[4] + 1.0)) is None  # not what rosbags decoded
    assert bulk_poses([raws[0][:30]], ros1, False, first) is None  # too short to hold a pose


def test_big_endian_cdr_is_left_to_rosbags() -> None:
    ts = get_typestore(Stores.ROS2_HUMBLE)
    little = messages(False, False, 'world', '', 1, 0)[0]
    message = ts.deserialize_cdr(little, POSE_STAMPED)
    big = bytes(ts.serialize_cdr(message, POSE_STAMPED, little_endian=False))
    assert bulk_poses([big], False, False, first_of(message, False)) is None
