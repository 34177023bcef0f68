"""``rps.utilities.sensors`` (V2): the seven distance sensors of each robot.

Each sensor sits at a point of the robot's body frame and looks along a body-frame angle
(``ARobotarium.DISTANCE_SENSORS_ORIENTATION``: rows x, y, angle). A reading is the distance along its ray to the
nearest line-segment obstacle or, with `simulate_distance_sensors`, the nearest other robot (a disc of the
robot's diameter, centred ``robot_center_offset`` ahead of the axle, where the sensors are mounted too). Nothing
within ``distance_sensor_range`` reads -1. A detection then goes through V2's noise model, drawn from
``np.random`` robot by robot and sensor by sensor as V2 draws it: dropped (-1) with ``distance_sensor_dropout_prob``,
otherwise an outlier uniform on [0, range) with ``distance_sensor_outlier_prob``, otherwise the true distance plus
Gaussian noise of standard deviation ``distance_sensor_error`` x distance, clipped to [0, range].
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def _rays(poses: FloatArray, mounts: FloatArray, reach: float) -> tuple[FloatArray, FloatArray]:
    """Start points and ray vectors (each 2 x S x N) of the sensors ``mounts`` (3 x S) on the robots ``poses``."""
    c, s = np.cos(poses[2]), np.sin(poses[2])
    start = np.stack(
        [
            c * mounts[0][:, None] - s * mounts[1][:, None] + poses[0],
            s * mounts[0][:, None] + c * mounts[1][:, None] + poses[1],
        ]
    )
    angle = poses[2][None, :] + mounts[2][:, None]
    return start, reach * np.stack([np.cos(angle), np.sin(angle)])


def _to_segments(start: FloatArray, ray: FloatArray, obstacles: FloatArray | None, reach: float) -> FloatArray:
    """Distance (S x N) along each ray to the nearest obstacle segment it crosses; ``reach`` if none."""
    nearest = np.full(start.shape[1:], reach)
    if obstacles is None or np.asarray(obstacles).size == 0:
        return nearest
    segments = np.asarray(obstacles, dtype=float)
    a = segments[:, 0, :][:, :, None, None]  # (M, 2, 1, 1): segment starts
    e = (segments[:, 1, :] - segments[:, 0, :])[:, :, None, None]  # segment directions
    cross = ray[0] * e[:, 1] - ray[1] * e[:, 0]  # (M, S, N)
    gap = a - start[None]
    with np.errstate(divide='ignore', invalid='ignore'):
        t = (gap[:, 0] * e[:, 1] - gap[:, 1] * e[:, 0]) / cross  # fraction of the ray
        u = (gap[:, 0] * ray[1] - gap[:, 1] * ray[0]) / cross  # fraction of the segment
    hit = (np.abs(cross) >= 1e-10) & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)
    lengths = np.where(hit, t * np.hypot(ray[0], ray[1]), np.inf)
    lengths_m: FloatArray = np.minimum(nearest, lengths.min(axis=0))
    return lengths_m


def _to_robots(start: FloatArray, ray: FloatArray, centres: FloatArray, radius: float) -> FloatArray:
    """Distance (S x N) along each ray to the nearest other robot's disc it enters ahead of the sensor; inf if none."""
    length = np.hypot(ray[0], ray[1])  # (S, N)
    unit = ray / length
    to_centre = centres[:, None, None, :] - start[:, :, :, None]  # (2, S, N, N_other)
    along = unit[0][:, :, None] * to_centre[0] + unit[1][:, :, None] * to_centre[1]
    closest = start[:, :, :, None] + along * unit[:, :, :, None]
    miss = np.hypot(*(closest - centres[:, None, None, :]))
    entry = along - np.sqrt(np.maximum(radius**2 - miss**2, 0.0))
    n = centres.shape[1]
    hit = (along >= 0) & (along <= length[:, :, None]) & (miss <= radius) & (entry >= 0) & ~np.eye(n, dtype=bool)[None]
    entries: FloatArray = np.where(hit, entry, np.inf).min(axis=2, initial=np.inf)
    return entries


def _readings(true: FloatArray, reach: float, error: float, dropout: float, outlier: float) -> FloatArray:
    """V2's noise model on the true distances (S x N), drawn robot by robot, sensor by sensor."""
    out = np.full(true.shape, -1.0)
    for i in range(true.shape[1]):
        for j in range(true.shape[0]):
            d = true[j, i]
            if not d < reach:
                continue
            if np.random.rand() < dropout:
                continue
            if np.random.rand() < outlier:
                out[j, i] = np.random.uniform(0, reach)
            else:
                out[j, i] = np.clip(d + error * d * np.random.randn(), 0, reach)
    return out


def simulate_distance_sensors_without_robots(
    poses: FloatArray,
    obstacles: FloatArray | None,
    distance_sensors_orientation: FloatArray,
    distance_sensor_range: float,
    distance_sensor_error: float,
    distance_sensor_dropout_prob: float,
    distance_sensor_outlier_prob: float,
) -> FloatArray:
    """Readings (7 x N, m; -1 where nothing is seen) of sensors mounted on the axle frame, seeing obstacles only."""
    start, ray = _rays(np.asarray(poses, dtype=float), distance_sensors_orientation, distance_sensor_range)
    true = _to_segments(start, ray, obstacles, distance_sensor_range)
    return _readings(
        true, distance_sensor_range, distance_sensor_error, distance_sensor_dropout_prob, distance_sensor_outlier_prob
    )


def simulate_distance_sensors(
    poses: FloatArray,
    obstacles: FloatArray | None,
    distance_sensors_orientation: FloatArray,
    robot_diameter: float,
    robot_center_offset: float,
    distance_sensor_range: float,
    distance_sensor_error: float,
    distance_sensor_dropout_prob: float,
    distance_sensor_outlier_prob: float,
) -> FloatArray:
    """Readings (7 x N, m; -1 where nothing is seen) of the sensors, seeing obstacles and the other robots."""
    poses = np.array(poses, dtype=float)
    poses[:2] += robot_center_offset * np.vstack([np.cos(poses[2]), np.sin(poses[2])])
    start, ray = _rays(poses, distance_sensors_orientation, distance_sensor_range)
    true = np.minimum(
        _to_segments(start, ray, obstacles, distance_sensor_range),
        _to_robots(start, ray, poses[:2], robot_diameter / 2),
    )
    return _readings(
        true, distance_sensor_range, distance_sensor_error, distance_sensor_dropout_prob, distance_sensor_outlier_prob
    )
