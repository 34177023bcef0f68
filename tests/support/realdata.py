"""Third-party recordings beside the project (never in it), and the MRCLAM set written into bags with rosbags.

The folder is ``$VTUBE_REALDATA`` or ``../shared/realdata`` from the repository root; tests that need it skip with
the reason when it is absent (a fresh clone has none). The benchmark uses the same writers.
"""

from __future__ import annotations

import os
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
    with Writer(path) as writer:  # in time order, as a recorder writes
        conns = {r: writer.add_connection(f'/vrpn_client_node/{r}/pose', msgtype, typestore=ts) for r in samples}
        for i, (t_ns, robot, x, y, theta) in enumerate(_in_time_order(samples)):
            header = T['std_msgs/msg/Header'](seq=i, stamp=_stamp(T, t_ns), frame_id='world')
            msg = T[msgtype](header=header, pose=_pose(T, x, y, theta))
            writer.write(conns[robot], t_ns, ts.serialize_ros1(msg, msgtype))
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
        for t_ns, robot, x, y, theta in rows:
            msg = T[tf_type](transforms=[transform(t_ns, 'world', robot, x, y, theta)])
            writer.write(tf, t_ns, ts.serialize_cdr(msg, tf_type))
    return path
