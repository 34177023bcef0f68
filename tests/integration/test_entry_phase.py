"""The entry phase flown whole: twenty robots of robotarium_trapezoid_20, two rows queued behind the entrance,
through the tube and parked, on the bundled simulator (theory §12)."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.design import WALL_CLEARANCE_M, start_formation
from robotarium_exp.experiment import ExperimentConfig, run_experiment
from robotarium_exp.rps.robotarium import Robotarium
from robotarium_exp.scene import load_scene
from robotarium_exp.tracking import plan_tracking
from robotarium_exp.verifier import VerifierCounts
from vtube_planning.planning.planner import plan_convex


@pytest.fixture(scope='module')
def run():
    scene = load_scene('robotarium_trapezoid_20')
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    result = run_experiment(
        Robotarium, scene, plan, ExperimentConfig(), robotarium_kwargs={'skip_initialization': True}
    )
    return scene, plan, result


def test_twenty_robots_pass_clean_and_park(run) -> None:
    scene, plan, result = run
    assert scene.swarm.n_robots == 20 and result.completed
    assert result.errors == VerifierCounts(too_close=0, outside=0, actuator=0)
    assert result.metrics.tube_violation_steps == 0  # no body on a wall
    assert result.metrics.min_distance_m > 0.135  # the testbed's collision distance between centres
    assert result.barrier.failures == 0
    dip = plan_tracking(result.arrays, plan, scene).dip.density_error_mean
    assert dip is not None and dip <= 0.25  # the sweep's bar


def test_the_queue_enters_through_the_entrance_row_after_row(run) -> None:
    scene, _, result = run
    l_m, clearance = result.arrays['l_m'], result.arrays['clearance_m']
    queued = np.flatnonzero(l_m[0] < 0.0)
    assert queued.size == 10  # two rows of five start behind the entrance, outside the tube
    crossing = np.argmax(l_m[:, queued] >= 0.0, axis=0)  # the first step each is in the tube
    assert np.all(l_m[crossing, queued] >= 0.0)
    # where it crosses l = 0, its centre is inside the entrance with room for its body: never through a wall
    assert np.all(clearance[crossing, queued] >= 0.5 * 0.11)
    rows = np.round(l_m[0, queued], 3)
    front, back = queued[rows == rows.max()], queued[rows == rows.min()]
    first = dict(zip(queued.tolist(), crossing.tolist()))
    assert max(first[k] for k in front) < min(first[k] for k in back)  # the front row is in before the back row
    assert start_formation(scene.tube, 20).queue
    assert np.all(
        np.abs(result.arrays['positions_m'][0, 1, queued]) <= scene.tube.half_width(0.0) - WALL_CLEARANCE_M + 1e-6
    )
