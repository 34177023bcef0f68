"""A trajectory written in the field's formats: a ROS 2 bag (MCAP or sqlite3) that Foxglove and RViz open, or CSV.

Each robot's poses become ``geometry_msgs/PoseStamped`` on ``/<robot>/pose`` in frame ``world`` (the layout
`robotarium_exp.analysis.bags` reads by default, so ``vtube analyze`` reads the bag back to the same frames),
stamped at the frame's time since the trajectory's first frame (a trajectory without headings gets the identity
orientation, heading 0); a frame where a robot has no position gives no message for it. With a scene the tube (its centre line and both walls) and the obstacles' outlines are one
``visualization_msgs/MarkerArray`` on ``/vtube/tube`` at the first frame, as line strips in the same frame. What a
vtube log records of its run (`RECORDED`: its scene, tube, flight start) goes into the bag's ``custom_data``, which
`robotarium_exp.analysis.bags` reads back. A bag is written whole in a hidden folder beside ``out`` and renamed. CSV:
one row per robot and frame with a position (``t_s,robot,x_m,y_m,heading_rad``; the heading empty when unknown).
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import shutil
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from robotarium_exp.analysis.trajectory import Trajectory
from robotarium_exp.errors import AnalysisError
from vtube_planning.files import write_atomically

if TYPE_CHECKING:
    from vtube_planning.geometry.scene import Scene

FORMATS = ('mcap', 'ros2', 'csv')
WORLD = 'world'
TUBE_TOPIC = '/vtube/tube'
POSE = 'geometry_msgs/msg/PoseStamped'
MARKERS = 'visualization_msgs/msg/MarkerArray'
CUSTOM_KEY = 'vtube'
"""The key of the bag's ``custom_data`` (``metadata.yaml``) that keeps what the source recorded of its run."""
RECORDED = ('scene', 'tube_hash', 'planned', 'flight_start', 'point_robots')
"""What a vtube log records of its run that the bag keeps (JSON under `CUSTOM_KEY`), so that ``vtube analyze`` of
the bag times the passage from the flight's start and judges the walls on the bodies, as of the log."""


def export(trajectory: Trajectory, out: Path, fmt: str, scene: Scene | None = None) -> Path:
    """Write ``trajectory`` to ``out`` in ``fmt`` (FORMATS: ``mcap`` and ``ros2`` are ROS 2 bag folders, MCAP or
    sqlite3 storage; ``csv`` a file); with ``scene``, its tube as markers in a bag. Returns ``out``."""
    if fmt not in FORMATS:
        msg = f'unknown format {fmt!r}; choose from {", ".join(FORMATS)}.'
        raise AnalysisError(msg)
    if fmt == 'csv':
        return write_atomically(out, _csv_text(trajectory))
    if out.exists():
        msg = f'{out} exists; a bag is a new folder: give another --out, or delete it.'
        raise AnalysisError(msg)
    out.parent.mkdir(parents=True, exist_ok=True)
    building = Path(tempfile.mkdtemp(prefix=f'.{out.name}.', suffix='.partial', dir=out.parent))
    try:  # written whole beside ``out`` and renamed: a failed export leaves nothing behind
        _write_bag(trajectory, building / 'bag', 'mcap' if fmt == 'mcap' else 'sqlite3', scene)
        os.rename(building / 'bag', out)
    finally:
        shutil.rmtree(building, ignore_errors=True)
    return out


def _csv_text(trajectory: Trajectory) -> str:
    text = io.StringIO()
    writer = csv.writer(text, lineterminator='\n')
    writer.writerow(['t_s', 'robot', 'x_m', 'y_m', 'heading_rad'])
    present = trajectory.present()
    for t in range(trajectory.t_s.size):
        for k in np.flatnonzero(present[t]):
            x, y = trajectory.positions_m[t, :, k]
            heading = '' if trajectory.headings_rad is None else repr(float(trajectory.headings_rad[t, k]))
            writer.writerow(
                [repr(float(trajectory.t_s[t])), trajectory.robot_ids[k], repr(float(x)), repr(float(y)), heading]
            )
    return text.getvalue()


def _write_bag(trajectory: Trajectory, out: Path, storage: str, scene: Scene | None) -> None:
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    stamps = np.round(trajectory.t_s * 1e9).astype(np.int64)
    plugin = StoragePlugin.MCAP if storage == 'mcap' else StoragePlugin.SQLITE3
    with Writer(out, version=9, storage_plugin=plugin) as writer:
        recorded = {key: trajectory.source.get(key) for key in RECORDED}
        if any(value is not None for value in recorded.values()):
            writer.set_custom_data(CUSTOM_KEY, json.dumps(recorded))
        if scene is not None:
            tube = writer.add_connection(TUBE_TOPIC, MARKERS, typestore=store)
            writer.write(tube, int(stamps[0]), bytes(store.serialize_cdr(_markers(store, scene), MARKERS)))
        present = trajectory.present()
        for k, name in enumerate(_topic_names(trajectory.robot_ids)):
            topic = writer.add_connection(f'/{name}/pose', POSE, typestore=store)
            for t in np.flatnonzero(present[:, k]):
                heading = 0.0 if trajectory.headings_rad is None else float(trajectory.headings_rad[t, k])
                x, y = trajectory.positions_m[t, :, k]
                pose = _pose_stamped(store, int(stamps[t]), float(x), float(y), heading)
                writer.write(topic, int(stamps[t]), bytes(store.serialize_cdr(pose, POSE)))


def _topic_names(robots: tuple[str, ...]) -> list[str]:
    """Each robot's topic name (`_topic_name`), made unique by its index where two ids give the same."""
    names = [_topic_name(robot) for robot in robots]
    return [f'{n}_{k}' if names.count(n) > 1 else n for k, n in enumerate(names)]


def _topic_name(robot: str) -> str:
    """A robot id as one name of a ROS topic (letters, digits and underscores, not starting with a digit)."""
    name = ''.join(c if c.isascii() and (c.isalnum() or c == '_') else '_' for c in robot)
    return name if name and not name[0].isdigit() else f'robot_{name}'


def _header(store: Any, t_ns: int) -> Any:
    T = store.types
    return T['std_msgs/msg/Header'](T['builtin_interfaces/msg/Time'](t_ns // 10**9, t_ns % 10**9), WORLD)


def _pose_stamped(store: Any, t_ns: int, x: float, y: float, heading: float) -> Any:
    T = store.types
    return T[POSE](
        _header(store, t_ns),
        T['geometry_msgs/msg/Pose'](
            T['geometry_msgs/msg/Point'](float(x), float(y), 0.0),
            T['geometry_msgs/msg/Quaternion'](0.0, 0.0, math.sin(heading / 2), math.cos(heading / 2)),
        ),
    )


def _markers(store: Any, scene: Scene) -> Any:
    """The tube's centre line and walls and the obstacles' outlines as line strips (ids in that order)."""
    tube = scene.tube
    l_m = np.linspace(0.0, tube.length_m, 400)
    lines = [(tube.center_at(l_m), (0.5, 0.5, 0.5)), *((wall, (0.1, 0.1, 0.1)) for wall in tube.boundaries(l_m))]
    if scene.obstacles is not None:
        lines += [(outline.T, (0.8, 0.2, 0.2)) for outline in scene.obstacles.outlines()]  # (2, K) -> (K, 2)
    return store.types[MARKERS]([_line(store, k, np.asarray(xy), rgb) for k, (xy, rgb) in enumerate(lines)])


def _line(store: Any, marker_id: int, xy: np.ndarray, rgb: tuple[float, float, float]) -> Any:
    """One line strip through the points ``xy`` (n, 2)."""
    T = store.types
    Marker = T['visualization_msgs/msg/Marker']
    point, vector = T['geometry_msgs/msg/Point'], T['geometry_msgs/msg/Vector3']
    return Marker(
        header=_header(store, 0),
        ns='vtube',
        id=marker_id,
        type=Marker.LINE_STRIP,
        action=Marker.ADD,
        pose=T['geometry_msgs/msg/Pose'](point(0.0, 0.0, 0.0), T['geometry_msgs/msg/Quaternion'](0.0, 0.0, 0.0, 1.0)),
        scale=vector(0.02, 0.0, 0.0),
        color=T['std_msgs/msg/ColorRGBA'](*rgb, 1.0),
        lifetime=T['builtin_interfaces/msg/Duration'](0, 0),
        frame_locked=False,
        points=[point(float(x), float(y), 0.0) for x, y in xy],
        colors=[],
        texture_resource='',
        texture=T['sensor_msgs/msg/CompressedImage'](_header(store, 0), '', np.zeros(0, dtype=np.uint8)),
        uv_coordinates=[],
        text='',
        mesh_resource='',
        mesh_file=T['visualization_msgs/msg/MeshFile']('', np.zeros(0, dtype=np.uint8)),
        mesh_use_embedded_materials=False,
    )
