"""The submission's body: it flies the flight data on a Robotarium class and saves what the testbed returns."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np

from robotarium_exp.analysis.loaders import load_trajectory
from robotarium_exp.experiment import ExperimentConfig, flight_data
from robotarium_exp.flight_data import FlightData
from robotarium_exp.scene import load_scene
from submission import runtime
from submission.runtime import META_FILE, draw_tube, save_log
from vtube_planning.planning.planner import plan_convex


def curve_data() -> FlightData:
    """The planned flight of robotarium_curve, as a submission embeds it (six significant digits)."""
    scene = load_scene('robotarium_curve')
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    return FlightData.from_plain(flight_data(scene, plan, ExperimentConfig()).to_plain())


def test_saved_arrays_load_without_pickle(tmp_path, monkeypatch) -> None:
    import importlib
    import sys

    from robotarium_exp.rps_classic import robotarium as classic
    from robotarium_exp.rps_import import CLASSIC

    for suffix in CLASSIC.modules:  # `import rps...` in the runtime resolves to the classic tree, for this test only
        monkeypatch.setitem(sys.modules, 'rps' + suffix, importlib.import_module('robotarium_exp.rps_classic' + suffix))

    class Module:  # robots placed at the initial conditions
        Robotarium = classic.Robotarium

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv('VTUBE_HEADLESS', '1')
    data = curve_data()
    summary = runtime.run(data, Module, max_steps=40)
    positions = np.load(tmp_path / 'vtube_positions_m.npy', allow_pickle=False)
    assert positions.shape == (summary['steps'], 2, 6)
    for name in ('t_s', 'headings_rad', 'dxu', 'r_a_m', 'points_l_m', 'density_per_m2', 'barrier_correction_mps'):
        assert np.load(tmp_path / f'vtube_{name}.npy', allow_pickle=False).shape[0] == summary['steps']
    meta = json.loads((tmp_path / 'vtube_meta.json').read_text())
    assert meta['format'] == 'vtube-trajectory' and meta['version'] == 2 and meta['finished']
    assert (
        meta['scene'] == 'robotarium_curve' and meta['tube_hash'] == load_scene('robotarium_curve').tube.fingerprint()
    )
    # the flight starts at the log's first row, after classic's (absent) initialization; 40 steps were sent
    assert meta['flight_start'] == {'iteration': 0, 'robotarium_time_s': 0.0, 't_s': 0.0}
    assert meta['iterations'] == summary['iterations'] == summary['steps'] == 40 and not meta['completed']
    returned = load_trajectory([tmp_path])  # the one reader of vtube logs
    assert returned.source['tube_hash'] == meta['tube_hash'] and len(returned.robot_ids) == 6
    assert returned.source['flight_start'] == meta['flight_start']
    np.testing.assert_array_equal(returned.positions_m, positions)


def test_the_log_is_saved_as_npy_files_and_a_description(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    save_log({'t_s': [np.float64(0.0), np.float64(0.033)], 'positions_m': [np.zeros((2, 3))] * 2}, {'finished': False})
    assert np.load(tmp_path / 'vtube_t_s.npy').tolist() == [0.0, 0.033]
    assert np.load(tmp_path / 'vtube_positions_m.npy').shape == (2, 2, 3)
    assert json.loads((tmp_path / META_FILE).read_text()) == {'finished': False}


def test_the_tube_and_the_obstacles_are_drawn_on_a_figure_only() -> None:
    drawn = []

    class Axes:
        def plot(self, x, y, **style) -> None:
            drawn.append(('line', list(x), list(y), style['color']))

        def fill(self, x, y, **style) -> None:
            drawn.append(('fill', list(x), list(y), style['color']))

    class WithFigure:
        _axes_handle = Axes()

    square = np.array([[0.0, 1.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 1.0, 0.0]])
    data = SimpleNamespace(tube_edges_m=np.arange(8.0).reshape(2, 2, 2), obstacle_outlines_m=(square,))
    draw_tube(WithFigure(), data)
    assert drawn == [
        ('line', [0.0, 1.0], [2.0, 3.0], 'tab:blue'),
        ('line', [4.0, 5.0], [6.0, 7.0], 'tab:blue'),
        ('fill', square[0].tolist(), square[1].tolist(), '0.55'),
    ]
    draw_tube(object(), data)  # no figure: nothing to draw on, no error

    class Classic:
        def __init__(self) -> None:
            self.axes: list = []  # the classic simulator's list when there is no figure

    draw_tube(Classic(), data)
    assert len(drawn) == 3
