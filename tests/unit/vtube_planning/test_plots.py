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


def test_the_animation_frames_the_whole_paths_with_robots_as_r_p_discs(scene, tmp_path) -> None:
    """Robots walk from before the entrance to well past the exit (where they used to leave the frame): every
    frame's robots lie inside the axes, drawn as discs of diameter 2 r_p in data units, on equal axes; the GIF is
    1280 px wide."""
    from matplotlib.collections import EllipseCollection
    from PIL import Image

    from vtube_planning.plots import GIF_WIDTH_PX, animate, animation_figure

    tube, n, steps, r_p = scene.tube, 5, 40, 0.04
    l_m = np.linspace(-0.3, tube.length_m + 0.6, steps)[:, None] + 0.1 * np.arange(n)[None, :]
    inside = tube.center_at(np.clip(l_m, 0.0, tube.length_m).ravel()).reshape(steps, n, 2)
    beyond = np.clip(l_m - tube.length_m, 0.0, None)[..., None] * np.array([1.0, 0.3])  # past the exit, drifting up
    before = np.clip(l_m, None, 0.0)[..., None] * np.array([1.0, 0.0])
    positions = (inside + beyond + before).transpose(0, 2, 1)
    result = SimpleNamespace(
        t_s=np.arange(steps) * 0.5,
        positions_m=positions,
        meta={'swarm': {'r_p_m': r_p}},
        planned=True,
        metrics=SimpleNamespace(passing_time_s=12.0),
    )
    fig, update = animation_figure(result, tube)  # type: ignore[arg-type]
    ax = fig.axes[0]
    (discs,) = [c for c in ax.collections if isinstance(c, EllipseCollection)]
    np.testing.assert_allclose(discs.get_widths(), 2 * r_p) and np.testing.assert_allclose(discs.get_heights(), 2 * r_p)
    assert ax.get_aspect() == 1.0
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert positions[:, 0].max() > tube.boundaries(np.array([tube.length_m]))[0][0, 0] + 0.5  # well past the exit
    for k in range(steps):
        update(k)
        xy = discs.get_offsets()
        np.testing.assert_allclose(xy, positions[k].T)
        assert (xy[:, 0] - r_p >= x0).all() and (xy[:, 0] + r_p <= x1).all()
        assert (xy[:, 1] - r_p >= y0).all() and (xy[:, 1] + r_p <= y1).all()
    assert ax.get_title().startswith('5 robots with planning (discs of radius r_p = 0.04 m)')
    assert ax.get_title().endswith(f't = {result.t_s[-1]:.1f} s')
    path = animate(result, tube, tmp_path / 'run.gif', frames=3)  # type: ignore[arg-type]
    with Image.open(path) as gif:
        assert gif.size[0] == GIF_WIDTH_PX and gif.n_frames == 3


def test_an_images_unknown_cells_are_drawn_and_say_what_they_count_as() -> None:
    """Issue 49: the figure drew only occupied pixels, so a tube across unmapped space looked clear."""
    from matplotlib.figure import Figure

    from vtube_planning.geometry.occupancy import OccupancyImage
    from vtube_planning.plots import UNKNOWN_RGBA, _draw_image

    unknown = np.array([[False, True], [False, False]])
    for free, said in ((False, 'unknown cells (occupied)'), (True, 'unknown cells (free)')):
        occupied = np.array([[True, False], [False, False]]) | (unknown & (not free))
        image = OccupancyImage(occupied, 1.0, (0.0, 0.0), unknown_cells=unknown, unknown_free=free)
        ax = Figure().add_subplot()
        _draw_image(ax, image, None)
        drawn = ax.images[0].get_array()
        assert tuple(drawn[0, 1]) == UNKNOWN_RGBA and drawn[1, 1, 3] == 0.0  # unknown coloured, free transparent
        assert [patch.get_label() for patch in ax.patches] == [said]
