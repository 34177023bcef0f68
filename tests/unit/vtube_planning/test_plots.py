"""Figures of scenes, plans and runs: the curves drawn are the objects' own values."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from robotarium_exp.scene import load_scene
from vtube_planning.planning.planner import plan_convex
from vtube_planning.plots import distance_figure, plan_figure, save_figure, scene_figure, snapshot_times
from vtube_planning.swarm.metrics import min_distance_over_time


@pytest.fixture(scope='module')
def scene():
    return load_scene('robotarium_trapezoid')


def line(ax, label: str):
    return next(ln for ln in ax.get_lines() if ln.get_label() == label)


def test_the_scene_figure_draws_the_half_width_the_curvature_and_the_workspace(scene) -> None:
    fig = scene_figure(scene)
    plane, width, curvature = fig.axes
    assert plane.get_title() == scene.title
    x, lam = width.get_lines()[0].get_data()
    np.testing.assert_allclose(lam, scene.tube.half_width(x))
    x, kappa = line(curvature, 'curvature kappa(l)').get_data()
    np.testing.assert_allclose(kappa, scene.tube.curvature(x))
    ws = scene.workspace
    outer = next(p for p in plane.patches if p.get_label() == 'workspace')
    assert (outer.get_x(), outer.get_y()) == (ws.x_min_m, ws.y_min_m)
    assert outer.get_width() == pytest.approx(ws.x_max_m - ws.x_min_m)
    left = line(plane, 'boundaries').get_xydata()
    np.testing.assert_allclose(left, scene.tube.boundaries(np.linspace(0.0, scene.tube.length_m, 1200))[0])


def test_the_plan_figure_draws_the_plans_speed_and_density(scene) -> None:
    plan = plan_convex(scene.tube, scene.swarm, scene.planning)
    fig = plan_figure(plan)
    ax_v, ax_rho, _, ax_act = fig.axes
    x, v = line(ax_v, 'planned speed v*').get_data()
    np.testing.assert_allclose(v, plan.speed(x))
    x, rho = line(ax_rho, 'planned density rho*').get_data()
    np.testing.assert_allclose(rho, plan.density(x))
    assert len(ax_act.collections) == sum(1 for k in ('v_max', 'v_min', 'p3', 'p4', 'p6', 'p7') if k in plan.active)


def test_snapshot_times_spread_evenly_over_the_run() -> None:
    assert snapshot_times(SimpleNamespace(t_s=np.arange(100)), 7) == [0, 16, 33, 49, 66, 82, 99]
    assert snapshot_times(SimpleNamespace(t_s=np.arange(3)), 7) == [0, 1, 2]


def test_the_distance_figure_draws_each_runs_minimum_distance_and_both_radii() -> None:
    rng = np.random.default_rng(0)
    meta = {'swarm': {'r_p_m': 0.1, 'r_s_m': 0.3}}
    runs = {k: SimpleNamespace(t_s=np.arange(5) * 0.1, positions_m=rng.normal(size=(5, 2, 4)), meta=meta) for k in 'ab'}
    ax = distance_figure(runs).axes[0]
    for k, run in runs.items():
        np.testing.assert_allclose(line(ax, k).get_ydata(), min_distance_over_time(run.positions_m))
    assert line(ax, '2 r_p (collision)').get_ydata()[0] == pytest.approx(0.2)
    assert line(ax, '2 r_s (safety)').get_ydata()[0] == pytest.approx(0.6)


def test_save_figure_makes_the_folder_and_writes_a_png(tmp_path, scene) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(1.0, 1.0))
    fig.add_subplot().plot([0, 1], [1, 0])
    path = save_figure(fig, tmp_path / 'a' / 'b.png', dpi=20)
    assert path == tmp_path / 'a' / 'b.png' and path.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'


def test_an_occupancy_image_is_drawn_pixel_for_pixel_over_its_extent() -> None:
    from matplotlib.figure import Figure

    from vtube_planning.geometry.obstacles import Obstacles
    from vtube_planning.geometry.occupancy import OccupancyImage
    from vtube_planning.plots import draw_tube

    occupied = np.zeros((3, 4), bool)
    occupied[0, 0] = True  # the top-left pixel
    image = OccupancyImage(occupied, 0.5, (10.0, 20.0))
    ax = Figure().add_subplot()
    draw_tube(ax, load_scene('robotarium_trapezoid').tube, obstacles=Obstacles(images=(image,)))
    (drawn,) = ax.get_images()
    assert tuple(drawn.get_extent()) == (10.0, 12.0, 20.0, 21.5) and drawn.origin == 'upper'
    alpha = np.asarray(drawn.get_array())[:, :, 3]
    assert alpha[0, 0] > 0 and alpha.sum() == alpha[0, 0]  # only the occupied pixel is painted
    assert ax.get_legend_handles_labels()[1].count('obstacles') == 1  # a legend entry, once
