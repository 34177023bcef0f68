"""The tube experiment on both Robotarium scenes, on the bundled simulator."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from robotarium_exp.design import order_for_v2_initializer
from robotarium_exp.errors import ExperimentError
from robotarium_exp.experiment import ExperimentConfig, flight_data, initial_conditions, run_experiment
from robotarium_exp.fit import fit_of_flight
from robotarium_exp.parking_slots import parking
from robotarium_exp.rps.robotarium import Robotarium
from robotarium_exp.scene import load_scene


def test_initial_conditions_are_spread_for_the_testbed() -> None:
    for name in ('robotarium_trapezoid', 'robotarium_curve'):
        scene = load_scene(name)
        ic = initial_conditions(scene)
        gaps = np.hypot(*(ic[:2, :, None] - ic[:2, None, :]))[np.triu_indices(ic.shape[1], 1)]
        assert ic.shape == (3, 6) and gaps.min() >= 0.4 - 1e-12
        assert np.all(np.abs(ic[0]) <= 1.375) and np.all(np.abs(ic[1]) <= 0.875)
        assert scene.tube.project(ic[:2]).inside.all()


@pytest.mark.parametrize(
    'name',
    [
        'robotarium_trapezoid',
        'robotarium_curve',
    ],
)
def test_parking_slots_keep_the_wall_the_testbed_turns_in(name: str) -> None:
    """The arena [-1.6, 1.6] x [-1, 1] less 0.2 m (the barrier's 0.1 m and 0.1 m to turn into a slot), to 1 mm."""
    scene = load_scene(name)
    slots = parking(scene.tube, scene.swarm.n_robots)
    assert np.all(np.abs(slots[0]) <= 1.4 + 1e-3) and np.all(np.abs(slots[1]) <= 0.8 + 1e-3)


def test_planning_without_a_plan_is_refused() -> None:
    with pytest.raises(ExperimentError, match='no plan was given'):
        run_experiment(Robotarium, load_scene('robotarium_curve'), None, ExperimentConfig())


def test_robots_zero_and_one_take_the_front_corners() -> None:
    """V2 never rescues robots 0 and 1 from a late deadlock: the least crowded slots, 0.8 m apart, take them."""
    ic = initial_conditions(load_scene('robotarium_trapezoid'))
    gaps = np.hypot(*(ic[:2, :, None] - ic[:2, None, :]))
    neighbours = (gaps < 0.5).sum(axis=0) - 1
    assert neighbours[0] == neighbours[1] == neighbours.min() == 2  # corners of the 2 x 3 formation
    assert ic[0, 0] == ic[0, 1] == ic[0].max()  # both in the front row
    grid = np.array([[0.0, 0.0, 0.0, -0.4, -0.4, -0.4], [-0.4, 0.0, 0.4, -0.4, 0.0, 0.4], [0.0] * 6])
    order = order_for_v2_initializer(grid)
    assert sorted(order) == list(range(6)) and set(order[:2]) == {0, 2}
    data = flight_data(load_scene('robotarium_trapezoid'), None, ExperimentConfig(planning=False))
    reasons = [str(m) for m in fit_of_flight(replace(data, initial_conditions=grid)).misfits]
    risk = [r for r in reasons if r.startswith('robots 0 and 1')]  # robot 1 in the middle of the front row
    assert risk and risk[0].startswith('robots 0 and 1 start 0.40 m apart')
    assert 'order_for_v2_initializer' in risk[0]
    ordered = [str(m) for m in fit_of_flight(replace(data, initial_conditions=grid[:, order])).misfits]
    assert not [r for r in ordered if r.startswith('robots 0 and 1')]


def test_a_short_run_logs_each_period_and_its_verdict(trapezoid, tmp_path) -> None:
    """Five periods without the initialization: every row logged, the recorder's columns consistent, the run not
    completed, its duration the simulator's iterations."""
    from vtube_planning.log import read_log

    scene, plan = trapezoid
    log = tmp_path / 'short.npz'
    result = run_experiment(
        Robotarium,
        scene,
        plan,
        ExperimentConfig(max_steps=5),
        log_path=log,
        robotarium_kwargs={'skip_initialization': True},
    )
    a = result.arrays
    assert not result.completed and result.planned and result.duration_s == pytest.approx(5 * 0.033)
    np.testing.assert_allclose(a['t_s'], 0.033 * np.arange(5))
    assert a['positions_m'].shape == (5, 2, 6) and a['dxu'].shape == (5, 2, 6) and a['flying'].all()
    np.testing.assert_allclose(a['positions_m'][0], initial_conditions(scene)[:2], atol=1e-6)
    change = a['si_safe_mps'] - a['si_nominal_mps']
    np.testing.assert_allclose(a['barrier_correction_mps'], np.hypot(change[:, 0], change[:, 1]))
    np.testing.assert_allclose(a['l_m'][3], scene.tube.project(a['positions_m'][3]).l_m)  # centres on the tube
    assert result.errors.clean and result.barrier.failures == 0
    arrays, meta = read_log(log)
    assert meta['finished'] and not meta['completed'] and meta['kind'] == 'robotarium experiment'
    assert meta['duration_s'] == pytest.approx(result.duration_s) and meta['errors'] == result.errors.to_json()
    np.testing.assert_array_equal(arrays['positions_m'], a['positions_m'])
