"""A 1 GB motion-capture bag analysed end to end: peak memory and time of ``vtube analyze``.

    python -m benchmarks.bag_memory [--gigabytes 1] [--bodies 10] [--keep FOLDER]

Writes a ROS 2 MCAP bag of PoseStamped messages in vrpn_mocap's layout (each body on its own topic at 120 Hz,
stamped 0.4 ms after the previous body, as vrpn_client_ros stamps them on arrival) until it holds the size asked
for, bodies on parallel lines 0.3 m apart moving along x: one capture is one frame, and the smallest distance is
0.3 m. Then, side by side in this process, a plain rosbags loop that reads every message without decoding it (the
floor of any analysis), and ``vtube analyze`` in a child process, whose peak resident memory is read from the
kernel (``ru_maxrss`` of the children). Targets (issue 34): peak memory under 1 GB and under 2 minutes on 2 cores;
the report must give one frame per capture and the 0.3 m minimum. ``--keep`` writes the bag once into FOLDER and
reuses it.
"""

from __future__ import annotations

import argparse
import json
import resource
import struct
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks._timing import timed

RATE_HZ, OFFSET_NS, SPACING_M, SPEED_MPS = 120.0, 400_000, 0.3, 0.2


def write_bag(path: Path, bodies: int, gigabytes: float) -> tuple[int, int]:
    """The bag (module doc); returns (captures, messages). Messages are one serialized template with the stamp
    and pose written into it (rosbags' serializer for each would take ten minutes)."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS2_HUMBLE)
    T = ts.types
    zero = T['geometry_msgs/msg/Point'](x=0.0, y=0.0, z=0.0)
    template = bytes(
        ts.serialize_cdr(
            T['geometry_msgs/msg/PoseStamped'](
                header=T['std_msgs/msg/Header'](
                    stamp=T['builtin_interfaces/msg/Time'](sec=0, nanosec=0), frame_id='world'
                ),
                pose=T['geometry_msgs/msg/Pose'](
                    position=zero, orientation=T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=0.0, w=1.0)
                ),
            ),
            'geometry_msgs/msg/PoseStamped',
        )
    )
    stamp_at, pose_at = 4, len(template) - 56  # CDR: the stamp after the 4-byte header; the pose's 7 doubles last
    period = int(1e9 / RATE_HZ)
    per_capture = bodies * (len(template) + 40)  # bytes per capture in MCAP, with its record and index (measured)
    captures = int(gigabytes * 1e9 / per_capture)
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        topics = [
            writer.add_connection(f'/vrpn_mocap/body_{k:02d}/pose', 'geometry_msgs/msg/PoseStamped', typestore=ts)
            for k in range(bodies)
        ]
        message = bytearray(template)
        for i in range(captures):
            for k, topic in enumerate(topics):
                t_ns = 1_700_000_000_000_000_000 + i * period + k * OFFSET_NS
                struct.pack_into('<iI', message, stamp_at, t_ns // 1_000_000_000, t_ns % 1_000_000_000)
                struct.pack_into(
                    '<dd', message, pose_at, SPEED_MPS * (t_ns - 1_700_000_000_000_000_000) * 1e-9, SPACING_M * k
                )
                writer.write(topic, t_ns, bytes(message))
    return captures, captures * bodies


def read_only(path: Path) -> int:
    """Every message read, none decoded."""
    from rosbags.rosbag2 import Reader

    count = 0
    with Reader(path) as reader:
        for _ in reader.messages():
            count += 1
    return count


def analyse(path: Path, out: Path) -> tuple[int, float]:
    """``vtube analyze`` in a child process: its exit code and peak resident memory (bytes)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    code = subprocess.call([sys.executable, '-m', 'vtube', 'analyze', str(path), '--out', str(out)])
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    if peak <= before:
        raise SystemExit('the child process did not raise the peak memory of the children: run this benchmark alone')
    return code, peak * 1024.0  # kilobytes on Linux


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--gigabytes', type=float, default=1.0)
    parser.add_argument('--bodies', type=int, default=10)
    parser.add_argument('--keep', type=Path, help='write the bag here once and reuse it')
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        path = (args.keep or Path(folder)) / f'mocap_{args.bodies}x{args.gigabytes:g}GB'
        if not path.exists():
            start = time.perf_counter()
            write_bag(path, args.bodies, args.gigabytes)
            print(f'wrote {path} in {time.perf_counter() - start:.0f} s')
        size = sum(f.stat().st_size for f in path.iterdir())
        t_read, messages = timed(lambda: read_only(path), 1)
        t_analyse, (code, peak) = timed(lambda: analyse(path, Path(folder) / 'report'), 1)
        metrics = json.loads((Path(folder) / 'report' / 'metrics.json').read_text()) if code == 0 else {}
    print(
        f'{size / 1e9:.2f} GB, {messages} PoseStamped messages ({args.bodies} bodies, {messages // args.bodies} captures)'
    )
    print(f'  rosbags, every message read, none decoded: {t_read:6.1f} s')
    print(f'  vtube analyze (exit {code}):                {t_analyse:6.1f} s ({t_analyse / t_read:.2f}x the reading)')
    print(f'  peak memory of vtube analyze: {peak / 1e9:.2f} GB ({peak / size:.2f} bytes per byte of bag)')
    if metrics:
        data = metrics['data']
        print(
            f'  frames: {data["frames"]} ({messages // args.bodies} captures); minimum distance {data["min_distance_m"]:.4f} m (0.3 by construction)'
        )


if __name__ == '__main__':
    main()
