"""Loading motion-capture bags, and analysing a real one end to end.

    python -m benchmarks.analysis_bench [--bodies 20] [--rate 120] [--seconds 300]

1. Writes a ROS2 sqlite3 bag with rosbags (vrpn_mocap topic layout; 20 bodies at 120 Hz for 5 minutes are
   720,000 PoseStamped messages), then times, in this process, vtube's ``load_trajectory`` (select topics,
   deserialize, map robots, put them on the union of their stamps) beside a plain ``AnyReader`` loop that only
   deserializes every message. Target: at most 1.3x the plain loop.
2. When the real recordings are beside the repository (``../shared/realdata`` or ``$VTUBE_REALDATA``), writes the
   MRCLAM set (five robots, 285,000 samples) into a ROS1 bag in vrpn_client_ros's layout and times ``vtube
   analyze`` on it end to end (read, assemble, measure, write metrics, report and figures), without a tube and in
   a scene. Target: under 10 s.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

from benchmarks._timing import timed
from robotarium_exp.analysis.loaders import load_trajectory
from tests.support.realdata import mrclam_samples, realdata_folder, write_mrclam_ros1
from vtube.cli import main as vtube


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
    if count != written:
        raise SystemExit(f'the plain loop read {count} of {written} messages')
    print(f'{written} messages ({args.bodies} bodies, {args.rate:g} Hz, {args.seconds:g} s)')
    print(f'  plain AnyReader loop (deserialize only): {t_plain:6.2f} s')
    print(
        f'  vtube load_trajectory:                   {t_ours:6.2f} s  ({t_ours / t_plain:.2f}x the plain loop), '
        f'{trajectory.positions_m.shape[0]} frames x {trajectory.n_robots} robots, '
        f'{int(np.isnan(trajectory.positions_m).any(axis=(1, 2)).sum())} incomplete frames'
    )
    folder = realdata_folder()
    if folder is None:
        print('MRCLAM end to end: skipped, the real recordings are not at ../shared/realdata ($VTUBE_REALDATA)')
        return
    samples = mrclam_samples(folder)
    with tempfile.TemporaryDirectory() as tmp:
        bag = write_mrclam_ros1(samples, Path(tmp) / 'mrclam.bag')
        base = ['analyze', str(bag), '--collision-distance', '0.35']
        runs = {
            'without a tube': [*base, '--out', str(Path(tmp) / 'free')],
            'in scene robotarium_trapezoid': [*base, '--scene', 'robotarium_trapezoid', '--out', str(Path(tmp) / 's')],
        }
        times = {label: timed(lambda argv=argv: vtube(argv), 1) for label, argv in runs.items()}
    print(f'MRCLAM ({sum(s.size for s, _ in samples.values())} messages, ROS1 bag) end to end:')
    for label, (seconds, code) in times.items():
        print(f'  vtube analyze {label + ":":32s} {seconds:6.2f} s (exit {code})')


if __name__ == '__main__':
    main()
