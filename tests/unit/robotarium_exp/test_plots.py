"""The experiment figure, drawn headless from a synthetic run: its panels, snapshots and marked moments."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from matplotlib.patches import Circle

from robotarium_exp.plots import experiment_figure
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
