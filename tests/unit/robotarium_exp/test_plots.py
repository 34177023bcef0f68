"""The experiment figure, drawn headless from a synthetic run: its panels, snapshots and marked moments; the scene
figure: the start formation, the parking slots, the start box and the verdict."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.patches import Circle, Rectangle

from robotarium_exp.design import parking, start_formation
from robotarium_exp.fit import robotarium_fit
from robotarium_exp.plots import experiment_figure, scene_figure
from robotarium_exp.scene import load_scene
from robotarium_exp.spec import ROBOTARIUM
from robotarium_exp.tracking import expansion_times
from robotarium_exp.verifier import VerifierCounts


def test_the_figure_draws_snapshots_radii_and_the_moments(trapezoid, marching) -> None:
    scene, plan = trapezoid
    result = SimpleNamespace(
        arrays=marching, errors=VerifierCounts(1, 0, 2), metrics=SimpleNamespace(min_distance_m=0.1834), planned=True
    )
    marching['flying'][-1, 0] = False  # one robot parked in the last snapshot: no radius drawn for it
    fig = experiment_figure(result, scene, plan)  # type: ignore[arg-type]
    arena, rho, speed, ra = fig.axes
    assert arena.get_title().startswith(f'{scene.name}, with planning: 1 too close, 0 outside, 2 actuator;')
    assert 'min distance 0.183 m' in arena.get_title()
    n = marching['l_m'].shape[1]
    circles = [p for p in arena.patches if isinstance(p, Circle)]
    bodies = [c for c in circles if np.isclose(c.get_radius(), 0.055)]
    assert len(bodies) == 7 * n and len(circles) - len(bodies) == 7 * n - 1
    assert [text.get_text() for text in arena.texts] == [
        f'{t:.0f} s' for t in marching['t_s'][[0, 49, 99, 149, 199, 249, 299]]
    ]
    expansion, front = expansion_times(marching, scene)
    for axis in (rho, speed):
        marks = sorted(line.get_xdata()[0] for line in axis.lines if line.get_linestyle() == ':')
        assert marks == sorted([expansion, front])
    labels = [line.get_label() for line in rho.lines]
    assert 'planned density' in labels and 'measured density' in labels and ra.get_ylabel() == 'r_a [m]'


def test_without_a_plan_no_planned_curves(trapezoid, marching) -> None:
    scene, _ = trapezoid
    result = SimpleNamespace(arrays=marching, errors=VerifierCounts(), metrics=SimpleNamespace(min_distance_m=0.3),
                             planned=False)  # fmt: skip
    fig = experiment_figure(result, scene)  # type: ignore[arg-type]
    assert 'without planning' in fig.axes[0].get_title()
    assert all('planned' not in line.get_label() for axis in fig.axes[1:3] for line in axis.lines)


@pytest.mark.parametrize('n', [6, 13])
def test_the_scene_figure_draws_the_formation_the_slots_and_the_verdict(n: int) -> None:
    scene = load_scene('robotarium_trapezoid', n_robots=n)
    fit = robotarium_fit(scene)
    ax = scene_figure(scene, fit).axes[0]
    circles = [p for p in ax.patches if isinstance(p, Circle)]
    bodies = [c for c in circles if np.isclose(c.get_radius(), 0.5 * ROBOTARIUM.robot_diameter_m)]
    bands = [c for c in circles if np.isclose(c.get_radius(), scene.swarm.r_s_m + scene.swarm.r_a_m)]
    formation = start_formation(scene.tube, n).poses[:2]
    assert len(bodies) == len(bands) == n
    np.testing.assert_allclose(np.array([c.center for c in bodies]).T, formation)
    assert sorted(t.get_text() for t in ax.texts if t.get_text().isdigit()) == sorted(map(str, range(n)))
    (slots,) = [line for line in ax.lines if line.get_label() == 'parking slots']
    np.testing.assert_allclose(np.array(slots.get_data()), parking(scene.tube, n))
    boxes = [p for p in ax.patches if isinstance(p, Rectangle) and p.get_label() == 'start box']
    assert len(boxes) == 1 and boxes[0].get_width() == 2 * ROBOTARIUM.ic_box_m[0]
    assert ax.get_title().endswith(f'({n} robots): {fit.reason}') and fit.fits is (
        n == 6
    )  # 13: the formation reaches the narrowing


def test_the_scene_figure_without_a_formation_still_draws_the_slots(tmp_path) -> None:
    path = tmp_path / 'edge.toml'
    path.write_text(
        '[tube.center]\nstart_xy_m = [-1.45, 0.88]\npieces = [{ kind = "line", length_m = 2.4 }]\n'
        '[tube.width]\nstart_m = 0.06\nparts = [{ kind = "constant" }]\n[robotarium]\nn_robots = 3\n'
    )
    scene = load_scene(path)
    fit = robotarium_fit(scene)
    ax = scene_figure(scene, fit).axes[0]
    assert not any(isinstance(p, Circle) and np.isclose(p.get_radius(), 0.055) for p in ax.patches)
    (slots,) = [line for line in ax.lines if line.get_label() == 'parking slots']
    assert np.array(slots.get_data()).shape == (2, 3) and 'no start formation' in ax.get_title()
