"""The experiment figure, drawn headless from a synthetic run: its panels, snapshots and marked moments; the scene
figure: the start formation, the parking slots, the start box and the verdict."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.patches import Circle, Rectangle

from robotarium_exp.design import start_formation
from robotarium_exp.fit import robotarium_fit
from robotarium_exp.parking_slots import parking
from robotarium_exp.plots import experiment_figure, scene_figure
from robotarium_exp.scene import load_scene
from robotarium_exp.spec import ROBOTARIUM
from robotarium_exp.tracking import expansion_times
from robotarium_exp.verifier import VerifierCounts


def _result(arrays, planned: bool = True, completed: bool = True, min_distance_m: float = 0.1834):
    return SimpleNamespace(
        arrays=arrays,
        errors=VerifierCounts(1, 0, 2),
        metrics=SimpleNamespace(min_distance_m=min_distance_m),
        planned=planned,
        completed=completed,
    )


def test_the_figure_draws_snapshots_radii_and_the_moments(trapezoid, marching) -> None:
    scene, plan = trapezoid
    marching['flying'][-1, 0] = False  # one robot parked in the last snapshot: no radius drawn for it
    fig = experiment_figure(_result(marching), scene, plan)  # type: ignore[arg-type]
    arena, rho, speed, bar, ra = fig.axes
    n = marching['l_m'].shape[1]
    assert arena.get_title().startswith(f'{scene.name} ({n} robots), with planning: 1 too close, 0 outside, 2 ')
    assert 'min distance 0.183 m' in arena.get_title()
    circles = [p for p in arena.patches if isinstance(p, Circle)]
    bodies = [c for c in circles if np.isclose(c.get_radius(), 0.055)]
    assert len(bodies) == 7 * n and len(circles) - len(bodies) == 7 * n - 1
    assert not arena.texts  # the snapshots' times are on the colour bar, not piled up above the arena
    assert bar.get_ylabel() == 'snapshot time [s]'
    snapshots = marching['t_s'][[0, 49, 99, 149, 199, 249, 299]]
    np.testing.assert_allclose(bar.get_yticks(), snapshots)
    assert [label.get_text() for label in bar.get_yticklabels()] == [f'{t:.0f}' for t in snapshots]
    expansion, front = expansion_times(marching, scene)
    for axis in (rho, speed):
        marks = sorted(line.get_xdata()[0] for line in axis.lines if line.get_linestyle() == ':')
        assert marks == sorted([expansion, front])
    labels = [line.get_label() for line in rho.lines]
    assert 'planned density' in labels and 'measured density' in labels and ra.get_ylabel() == 'r_a [m]'
    cut = [text.get_text().strip() for text in rho.texts]
    assert cut == [f"robot 0 parks at {marching['t_s'][-1]:.1f} s:\nthe swarm's density, r_a and plan end"]


def _drawn_points(axis) -> int:
    """Finite points drawn in lines and collections (a band's polygon counts its vertices)."""
    points = sum(
        int(np.isfinite(np.asarray(line.get_xydata())).all(axis=1).sum())
        for line in axis.lines
        if len(line.get_xdata()) > 2
    )  # fmt: skip  (a mark's line has two points)
    return points + sum(len(path.vertices) for c in axis.collections for path in c.get_paths())


def n_robots_run(trapezoid, n: int, parks: list[int]) -> dict[str, np.ndarray]:
    """A synthetic run of ``n`` robots on the trapezoid: robot k walks at its own speed and parks at step
    ``parks[k]`` (past the run's end: never)."""
    scene, plan = trapezoid
    steps = 300
    center = np.linspace(-0.1, scene.tube.length_m + 0.1, steps)
    l_m = center[:, None] + 0.05 * (np.arange(n) - (n - 1) / 2)[None, :]
    flying = np.arange(steps)[:, None] < np.asarray(parks)[None, :]
    dxu = np.zeros((steps, 2, n))
    dxu[:, 0, :] = plan.speed(center)[:, None] * (1.0 + 0.02 * np.arange(n))[None, :]
    xy = scene.tube.center_at(np.clip(l_m, 0.0, scene.tube.length_m).ravel())
    return {
        't_s': np.arange(steps) * 0.1,
        'l_m': l_m,
        'positions_m': np.asarray(xy).reshape(steps, n, 2).transpose(0, 2, 1),
        'dxu': dxu,
        'r_a_m': np.full((steps, n), 0.1),
        'density_per_m2': plan.density(center),
        'flying': flying,
    }


@pytest.mark.parametrize('n', [1, 6, 20])
def test_the_lower_panels_hold_data_and_say_where_the_swarm_curves_end(trapezoid, n: int) -> None:
    """Robots park one after another from step 120 on: the swarm's curves end there and the panel says so; the
    speed goes on for the robots still flying (median and band) up to the last one's parking, which sets the time
    axis; the snapshots' times are readable (seven distinct labels) whatever the number of robots."""
    scene, plan = trapezoid
    parks = [120 + 5 * k for k in range(n)]
    arrays = n_robots_run(trapezoid, n, parks)
    fig = experiment_figure(_result(arrays, min_distance_m=np.inf if n == 1 else 0.2), scene, plan)  # type: ignore[arg-type]
    arena, rho, speed, bar, ra = fig.axes
    assert _drawn_points(rho) >= 2 * 120 and _drawn_points(ra) >= 120 and _drawn_points(speed) >= parks[-1]
    assert len(speed.collections) == (n > 1)  # a band for more than one robot
    (median,) = [line for line in speed.lines if line.get_linestyle() == '-']
    assert median.get_xdata()[-1] == arrays['t_s'][parks[-1] - 1]
    assert speed.get_xlim()[1] == pytest.approx(1.02 * arrays['t_s'][parks[-1] - 1])
    (said,) = rho.texts
    assert said.get_text().strip().startswith("robot 0 parks at 12.0 s:\nthe swarm's density")
    assert max(len(line.get_xdata()) for line in rho.lines) == 120  # and no further
    said = [text.get_text().strip() for text in speed.texts]
    assert said == ([] if n == 1 else ['from 12.0 s: the robots still flying'])
    assert len({label.get_text() for label in bar.get_yticklabels()}) == 7
    assert ('no two robots' in arena.get_title()) is (n == 1)


def test_a_panel_with_nothing_to_draw_says_so(trapezoid) -> None:
    scene, plan = trapezoid
    arrays = n_robots_run(trapezoid, 20, [0] + [150] * 19)  # robot 0 parked from the start
    rho, speed = experiment_figure(_result(arrays, completed=False), scene, plan).axes[1:3]  # type: ignore[arg-type]
    texts = [text.get_text() for text in rho.texts]
    assert 'robot 0 is parked from the start: no step with every robot flying' in texts
    assert _drawn_points(speed) >= 150
    arrays['flying'][:] = False
    rho, speed = experiment_figure(_result(arrays, completed=False), scene, plan).axes[1:3]  # type: ignore[arg-type]
    assert all(axis.texts[0].get_text() == 'no robot flies the tube in this run' for axis in (rho, speed))
    arrays['flying'][:] = True
    speed = experiment_figure(_result(arrays, completed=False), scene, plan).axes[2]  # type: ignore[arg-type]
    assert speed.texts[-1].get_text() == 'run stopped, 20 robot(s) flying '


def test_without_a_plan_no_planned_curves(trapezoid, marching) -> None:
    scene, _ = trapezoid
    fig = experiment_figure(_result(marching, planned=False), scene)  # type: ignore[arg-type]
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
