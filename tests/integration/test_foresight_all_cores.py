"""A large swarm's foresight on all cores (numba's threads) flies the same bits as on one: the parallel builds of the
predictions, the check and the nearest-point search against their serial builds, and a period of a swarm above
`ALL_CORES_FROM` against the same period predicted on one core. (Here, not among the unit tests: the parallel builds
are compiled on first use, not cached, about 20 s.)"""

from __future__ import annotations

import numpy as np

from tests.unit.vtube_planning.swarm.test_foresight_kernel import LOCATE, LOOKAHEAD_S, R_P, R_S, TIMES, _swarm
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.params import SwarmParams
from vtube_planning.swarm import foresight as foresight_module
from vtube_planning.swarm.foresight import Foresight
from vtube_planning.swarm.foresight_kernel import flights, foresee, parallel_flights, parallel_foresee
from vtube_planning.swarm.nearest import nearest


def test_the_parallel_builds_compute_the_serial_bits() -> None:
    rng = np.random.default_rng(21)
    tables, robots = _swarm(rng, 400)
    rows = np.arange(400)
    lane, speed_to = rng.uniform(-1.0, 1.0, (400, 3)), rng.uniform(2.0, 5.0, (400, 3))
    first = np.stack([speed_to, np.where(rng.random((400, 3)) < 0.5, 0.2, np.nan)])
    limits = np.array([1.0, 1.0, R_S, LOOKAHEAD_S, LOCATE])
    flown = flights(robots, rows, lane, speed_to, first, TIMES, tables.compiled, limits)
    np.testing.assert_array_equal(
        parallel_flights(robots, rows, lane, speed_to, first, TIMES, tables.compiled, limits), flown
    )
    near = nearest(robots[0], robots[1], robots[0], robots[1], 21)
    np.testing.assert_array_equal(nearest(robots[0], robots[1], robots[0], robots[1], 21, all_cores=True), near)
    others, seen = np.ascontiguousarray(flown[:2, :, :, :2]), rng.integers(0, 2, near.shape)
    bounds = np.array([R_S, R_P, 0.1, 40.0])
    found = foresee(flown, others, robots, rows, near, seen, TIMES, tables.compiled, bounds)
    np.testing.assert_array_equal(
        parallel_foresee(flown, others, robots, rows, near, seen, TIMES, tables.compiled, bounds), found
    )


def test_a_period_of_a_large_swarm_is_the_same_on_all_cores_and_on_one(monkeypatch) -> None:
    n = foresight_module.ALL_CORES_FROM
    side = int(np.ceil(np.sqrt(n)))
    length, half_width = 2.2 * side + 30.0, 1.1 * side + 1.0
    tube = VirtualTube(ArcPath((ArcPiece(length),)), WidthProfile(half_width, (WidthPart('constant', length),)))
    k = np.arange(n)
    rng = np.random.default_rng(22)
    positions = np.vstack([5.0 + 2.2 * (k // side), -half_width + 1.0 + 2.2 * (k % side)])
    positions = positions + rng.normal(0.0, 0.6, positions.shape)  # close enough somewhere for backups
    velocity = np.vstack([np.full(n, 3.0), rng.normal(0.0, 0.3, n)])
    commands = []
    for threshold in (n, n + 1):  # all cores, then one
        monkeypatch.setattr(foresight_module, 'ALL_CORES_FROM', threshold)
        swarm = SwarmParams(n_robots=n)
        foresight = Foresight(tube, swarm, horizon_s=3.0, acceleration_limits=True)
        commands.append([foresight(positions, velocity, velocity, 0.02) for _ in range(2)])
        overridden = foresight.overridden
    np.testing.assert_array_equal(commands[0], commands[1])
    assert overridden > 0  # the backups were chosen too, not only the law's commands checked
