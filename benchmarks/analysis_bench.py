"""Loading a motion-capture bag: 20 bodies at 120 Hz for 5 minutes (720,000 PoseStamped messages).

    python -m benchmarks.analysis_bench [--bodies 20] [--rate 120] [--seconds 300] [--keep DIR]

Writes a ROS2 sqlite3 bag with rosbags (vrpn_mocap topic layout), then times, in this process, vtube's
``load_trajectory`` (select topics, deserialize, map robots, put them on common stamps) beside a plain
``AnyReader`` loop that only deserializes every message. Target: under 15 s on a 2-core machine.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

from benchmarks._timing import timed
from robotarium_exp.analysis.loaders import load_trajectory


def write_bag(path: Path, bodies: int, rate: float, seconds: float) -> int:
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS2_HUMBLE)
    T = ts.types
    period_ns = int(1e9 / rate)
    steps = int(seconds * rate)
    count = 0
    with Writer(path, version=9) as writer:
        conns = [
            writer.add_connection(f'/vrpn_mocap/body_{k:02d}/pose', 'geometry_msgs/msg/PoseStamped', typestore=ts)
            for k in range(bodies)
        ]
        quat = T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=0.0, w=1.0)
        for i in range(steps):
            t_ns = 1_700_000_000_000_000_000 + i * period_ns
            stamp = T['builtin_interfaces/msg/Time'](sec=t_ns // 10**9, nanosec=t_ns % 10**9)
            header = T['std_msgs/msg/Header'](stamp=stamp, frame_id='world')
            for k, conn in enumerate(conns):
                point = T['geometry_msgs/msg/Point'](x=0.001 * i, y=0.1 * k, z=0.0)
                msg = T['geometry_msgs/msg/PoseStamped'](
                    header=header, pose=T['geometry_msgs/msg/Pose'](position=point, orientation=quat)
                )
                writer.write(conn, t_ns, ts.serialize_cdr(msg, 'geometry_msgs/msg/PoseStamped'))
                count += 1
    return count


def plain_loop(path: Path) -> int:
    from rosbags.highlevel import AnyReader

    count = 0
    with AnyReader([path]) as reader:
        for connection, _, raw in reader.messages(connections=reader.connections):
            reader.deserialize(raw, connection.msgtype)
            count += 1
    return count


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--bodies', type=int, default=20)
    parser.add_argument('--rate', type=float, default=120.0)
    parser.add_argument('--seconds', type=float, default=300.0)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / 'mocap'
        written = write_bag(path, args.bodies, args.rate, args.seconds)
        t_plain, count = timed(lambda: plain_loop(path), 1)
        t_ours, trajectory = timed(lambda: load_trajectory([path]), 1)
    assert count == written
    print(f'{written} messages ({args.bodies} bodies, {args.rate:g} Hz, {args.seconds:g} s)')
    print(f'  plain AnyReader loop (deserialize only): {t_plain:6.2f} s')
    print(
        f'  vtube load_trajectory:                   {t_ours:6.2f} s  ({t_ours / t_plain:.2f}x the plain loop), '
        f'{trajectory.positions_m.shape[0]} frames x {trajectory.n_robots} robots, '
        f'{int(np.isnan(trajectory.positions_m).any(axis=(1, 2)).sum())} incomplete frames'
    )


if __name__ == '__main__':
    main()
