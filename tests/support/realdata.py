"""Third-party recordings beside the project (never in it), and the MRCLAM set written into bags with rosbags.

The folder is ``$VTUBE_REALDATA`` or ``../shared/realdata`` from the repository root; tests that need it skip with
the reason when it is absent (a fresh clone has none). The benchmark uses the same writers.
"""

from __future__ import annotations

import math
import os
import struct
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
MRCLAM_ROBOTS = tuple(f'Robot{k}' for k in range(1, 6))


def realdata_folder() -> Path | None:
    """The recordings' folder, or None when it is not there."""
    folder = Path(os.environ.get('VTUBE_REALDATA', ROOT.parent / 'shared' / 'realdata'))
    return folder if folder.is_dir() else None


def mrclam_samples(folder: Path) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each MRCLAM robot's raw samples: stamps in integer nanoseconds (the files give milliseconds) and (x, y, theta)."""
    samples = {}
    for robot in MRCLAM_ROBOTS:
        data = np.loadtxt(folder / 'mrclam6' / f'{robot}_Groundtruth.dat', comments='#')
        stamps = np.round(data[:, 0] * 1000).astype(np.int64) * 1_000_000
        samples[robot] = (stamps, data[:, 1:4])
    return samples


def _pose(T, x: float, y: float, theta: float):
    return T['geometry_msgs/msg/Pose'](
        position=T['geometry_msgs/msg/Point'](x=x, y=y, z=0.0),
        orientation=T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=np.sin(theta / 2), w=np.cos(theta / 2)),
    )


def _stamp(T, t_ns: int):
    return T['builtin_interfaces/msg/Time'](sec=int(t_ns) // 10**9, nanosec=int(t_ns) % 10**9)


def _in_time_order(samples: dict[str, tuple[np.ndarray, np.ndarray]]) -> list[tuple[int, str, float, float, float]]:
    return sorted(
        (t_ns, robot, x, y, theta)
        for robot, (stamps, values) in samples.items()
        for t_ns, (x, y, theta) in zip(stamps.tolist(), values.tolist(), strict=True)
    )


def write_mrclam_ros1(samples: dict[str, tuple[np.ndarray, np.ndarray]], path: Path) -> Path:
    """A ROS1 bag in vrpn_client_ros's layout: /vrpn_client_node/<robot>/pose, PoseStamped in frame 'world'."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS1_NOETIC)
    T = ts.types
    msgtype = 'geometry_msgs/msg/PoseStamped'

    def message(seq: int, t_ns: int, x: float, y: float, theta: float) -> bytes:
        header = T['std_msgs/msg/Header'](seq=seq, stamp=_stamp(T, t_ns), frame_id='world')
        return bytes(ts.serialize_ros1(T[msgtype](header=header, pose=_pose(T, x, y, theta)), msgtype))

    fast = _Patched(message, '<', with_seq=True)
    with Writer(path) as writer:  # in time order, as a recorder writes
        conns = {r: writer.add_connection(f'/vrpn_client_node/{r}/pose', msgtype, typestore=ts) for r in samples}
        for i, (t_ns, robot, x, y, theta) in enumerate(_in_time_order(samples)):
            writer.write(conns[robot], t_ns, fast(i, t_ns, x, y, theta, check=i % CHECK_EVERY == 0))
    return path


def write_mrclam_tf(samples: dict[str, tuple[np.ndarray, np.ndarray]], path: Path) -> Path:
    """A ROS2 MCAP bag with every robot on /tf (parent 'world', child = robot), a static 'world' -> 'vicon' frame
    on /tf_static, and a topic of a type vtube does not read."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS2_HUMBLE)
    T = ts.types
    tf_type = 'tf2_msgs/msg/TFMessage'

    def transform(t_ns: int, parent: str, child: str, x: float, y: float, theta: float):
        q = _pose(T, x, y, theta).orientation
        return T['geometry_msgs/msg/TransformStamped'](
            header=T['std_msgs/msg/Header'](stamp=_stamp(T, t_ns), frame_id=parent),
            child_frame_id=child,
            transform=T['geometry_msgs/msg/Transform'](
                translation=T['geometry_msgs/msg/Vector3'](x=x, y=y, z=0.0), rotation=q
            ),
        )

    rows = _in_time_order(samples)
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        static = writer.add_connection('/tf_static', tf_type, typestore=ts)
        tf = writer.add_connection('/tf', tf_type, typestore=ts)
        other = writer.add_connection('/battery', 'sensor_msgs/msg/BatteryState', typestore=ts)
        first = rows[0][0]
        writer.write(
            static,
            first,
            ts.serialize_cdr(T[tf_type](transforms=[transform(first, 'world', 'vicon', 1, 2, 0)]), tf_type),
        )
        battery = T['sensor_msgs/msg/BatteryState'](
            header=T['std_msgs/msg/Header'](stamp=_stamp(T, first), frame_id=''),
            voltage=12.0,
            temperature=20.0,
            current=0.0,
            charge=1.0,
            capacity=1.0,
            design_capacity=1.0,
            percentage=1.0,
            power_supply_status=0,
            power_supply_health=0,
            power_supply_technology=0,
            present=True,
            cell_voltage=np.zeros(0, dtype=np.float32),
            cell_temperature=np.zeros(0, dtype=np.float32),
            location='',
            serial_number='',
        )
        writer.write(other, first, ts.serialize_cdr(battery, 'sensor_msgs/msg/BatteryState'))
        fast = {
            robot: _Patched(
                lambda _seq, t_ns, x, y, theta, robot=robot: bytes(
                    ts.serialize_cdr(T[tf_type](transforms=[transform(t_ns, 'world', robot, x, y, theta)]), tf_type)
                ),
                '<',
                with_seq=False,
            )
            for robot in samples
        }
        for i, (t_ns, robot, x, y, theta) in enumerate(rows):
            writer.write(tf, t_ns, fast[robot](0, t_ns, x, y, theta, check=i % CHECK_EVERY == 0))
    return path


CHECK_EVERY = 500
"""Every this many messages the patched bytes are checked against rosbags' own serialization."""


class _Patched:
    """A message's bytes by patching the numbers into one serialization made by rosbags (the layout is fixed:
    same frame names, one transform), instead of building and serializing 285,000 message objects.

    The offsets are found by serializing once with sentinel values, each of which must occur exactly once.
    """

    SEQ, SEC, NSEC = 3_141_592_653, 1_234_567_891, 987_654_321
    X, Y, THETA = -123.456789012345, 234.567890123456, 0.123456789

    def __init__(self, message, order: str, *, with_seq: bool) -> None:
        self.message, self.order, self.with_seq = message, order, with_seq
        self.template = message(self.SEQ, self.SEC * 10**9 + self.NSEC, self.X, self.Y, self.THETA)
        half = self.THETA / 2
        fields = [('I', self.SEC), ('I', self.NSEC), ('d', self.X), ('d', self.Y), ('d', math.sin(half))]
        fields += [('d', math.cos(half))] + ([('I', self.SEQ)] if with_seq else [])
        self.offsets = [self._offset(code, value) for code, value in fields]

    def _offset(self, code: str, value: float) -> int:
        packed = struct.pack(self.order + code, value)
        assert self.template.count(packed) == 1, f'sentinel {value!r} is not unique in the template'
        return self.template.index(packed)

    def __call__(self, seq: int, t_ns: int, x: float, y: float, theta: float, *, check: bool = False) -> bytes:
        buffer = bytearray(self.template)
        sec, nsec = divmod(int(t_ns), 10**9)
        values = [sec, nsec, x, y, math.sin(theta / 2), math.cos(theta / 2)] + ([seq] if self.with_seq else [])
        for (offset, code), value in zip(zip(self.offsets, 'IIdddd' + 'I' * self.with_seq), values, strict=True):
            struct.pack_into(self.order + code, buffer, offset, value)
        if check:
            assert bytes(buffer) == self.message(seq, t_ns, x, y, theta), "patched bytes differ from rosbags'"
        return bytes(buffer)
