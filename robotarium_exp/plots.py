"""Figures of Robotarium experiments. matplotlib is imported here only, when a figure is drawn."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.plots import draw_tube

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from robotarium_exp.experiment import ExperimentResult
    from robotarium_exp.fit import Fit
    from vtube_planning.geometry.scene import Scene
    from vtube_planning.planning.plan import Plan


def experiment_figure(result: ExperimentResult, scene: Scene, plan: Plan | None = None) -> Figure:
    """The paper's Robotarium figure: the arena with the tube, paths and snapshots (colour = time) with every robot's
    avoidance radius drawn; below, the planned and measured density, speed and r_a over time, with the moment
    the expansion starts and the moment the front reaches the narrowing."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 10.5), layout='constrained')
    ax, ax_rho, ax_v = fig.subplots(3, 1, height_ratios=[2.2, 1, 1], sharex=False)
    _arena_panel(ax, result, scene)
    _time_panels(ax_rho, ax_v, result, scene, plan)
    return fig


def _arena_panel(ax: Axes, result: ExperimentResult, scene: Scene) -> None:
    """The arena, the tube, the paths and seven snapshots of the robots with their avoidance radii."""
    from matplotlib import colormaps
    from matplotlib.patches import Circle, Rectangle

    arrays = result.arrays
    t = arrays['t_s']
    draw_tube(ax, scene.tube, n_sections=8, obstacles=scene.obstacles)
    xmin, xmax, ymin, ymax = ROBOTARIUM.arena_m
    ax.add_patch(Rectangle((xmin, ymin), xmax - xmin, ymax - ymin, fill=False, ec='k', lw=1.2))
    cmap = colormaps['viridis']
    poses = arrays['positions_m']
    for k in range(poses.shape[2]):
        ax.plot(poses[:, 0, k], poses[:, 1, k], color='0.6', lw=0.6)
    placed: list[float] = []  # the x of each time label so far
    for step in np.unique(np.linspace(0, t.size - 1, 7).astype(int)):
        color = cmap(step / max(1, t.size - 1))
        for k in range(poses.shape[2]):
            center = (float(poses[step, 0, k]), float(poses[step, 1, k]))
            ax.add_patch(Circle(center, 0.5 * ROBOTARIUM.robot_diameter_m, fc=color, ec='k', lw=0.4, zorder=3))
            if arrays['flying'][step, k]:
                radius = float(arrays['r_a_m'][step, k])
                ax.add_patch(Circle(center, radius, fill=False, ec=color, lw=0.6, ls='--', zorder=2))
        # the times in a row above the arena, over each snapshot's centre; a second row where two stand close
        x = float(poses[step, 0].mean())
        row = 1 if placed and abs(x - placed[-1]) < 0.2 else 0
        placed.append(x if row == 0 else placed[-1] + 1.0)
        ax.annotate(f'{t[step]:.0f} s', (x, ymax + 0.04 + 0.08 * row), ha='center', fontsize=7, color=color)
    ax.set_xlim(xmin - 0.1, xmax + 0.1)
    ax.set_ylim(ymin - 0.1, ymax + 0.22)
    ax.set_aspect('equal')
    e, m = result.errors, result.metrics
    ax.set_title(
        f'{scene.name}, {"with" if result.planned else "without"} planning: '
        f'{e.too_close} too close, {e.outside} outside, {e.actuator} actuator;\nmin distance {m.min_distance_m:.3f} m; '
        "dashed circles: each robot's avoidance radius r_a",
        fontsize=10,
    )


def _time_panels(ax_rho: Axes, ax_v: Axes, result: ExperimentResult, scene: Scene, plan: Plan | None) -> None:
    """Density and r_a, and speed, over time while every robot flies, planned and measured, with the moments the
    expansion starts and the front reaches the narrowing."""
    from robotarium_exp.tracking import expansion_times

    arrays = result.arrays
    t = arrays['t_s']
    swarm = arrays['flying'].all(axis=1)  # until the first robot parks
    center = arrays['l_m'].mean(axis=1)
    ax_rho.plot(t[swarm], arrays['density_per_m2'][swarm], color='tab:green', label='measured density')
    ax_v.plot(t[swarm], arrays['dxu'][swarm, 0, :].mean(axis=1), color='tab:blue', label='mean forward speed')
    if plan is not None:
        ax_rho.plot(t[swarm], plan.density(center[swarm]), color='tab:green', ls='--', label='planned density')
        ax_v.plot(t[swarm], plan.speed(center[swarm]), color='tab:blue', ls='--', label='planned speed')
    ax_ra = ax_rho.twinx()
    ra = arrays['r_a_m'].mean(axis=1)
    ax_ra.plot(t[swarm], ra[swarm], color='tab:purple', label='mean r_a')
    ax_ra.set_ylabel('r_a [m]')
    expansion_s, narrowing_s = expansion_times(arrays, scene)
    for axis in (ax_rho, ax_v):
        if expansion_s is not None:
            axis.axvline(expansion_s, color='tab:purple', ls=':', lw=1.0, label='expansion starts')
        if narrowing_s is not None:
            axis.axvline(narrowing_s, color='k', ls=':', lw=1.0, label='front reaches the narrowing')
        axis.set_xlabel('time [s]')
    handles, labels = ax_rho.get_legend_handles_labels()
    more = ax_ra.get_legend_handles_labels()
    above: dict[str, Any] = {
        'loc': 'lower left',
        'bbox_to_anchor': (0.0, 1.01),
        'ncols': 3,
        'fontsize': 7,
        'frameon': False,
    }
    ax_rho.legend(handles + more[0], labels + more[1], **above)  # above the curves, never over them
    ax_v.legend(**above)
    ax_rho.set_ylabel('density [1/m^2]')
    ax_v.set_ylabel('speed [m/s]')


def scene_figure(scene: Scene, fit: Fit) -> Figure:
    """The scene's figure (`vtube_planning.plots.scene_figure`) with what the Robotarium adds: the start
    formation (bodies, and the interaction band r_s + r_a dashed), the parking slots, the box the testbed
    initializes robots in, and the fit verdict in the title."""
    from matplotlib.patches import Circle, Rectangle

    from robotarium_exp.design import parking, start_formation
    from vtube_planning.plots import scene_figure as tube_figure

    fig = tube_figure(scene)
    ax = fig.axes[0]
    formation = start_formation(scene.tube, scene.swarm.n_robots)
    band = scene.swarm.r_s_m + scene.swarm.r_a_m
    if formation.problem is None:
        for k, (x, y) in enumerate(formation.poses[:2].T):
            ax.add_patch(Circle((x, y), 0.5 * ROBOTARIUM.robot_diameter_m, fc='tab:blue', ec='k', lw=0.5, zorder=3))
            ax.add_patch(Circle((x, y), band, fill=False, ec='tab:blue', lw=0.5, ls='--', zorder=2))
            ax.annotate(str(k), (x, y), ha='center', va='center', fontsize=6, color='w', zorder=4)
    slots = parking(scene.tube, scene.swarm.n_robots)
    ax.plot(slots[0], slots[1], 'x', color='tab:red', ms=6, label='parking slots')
    box_x, box_y = ROBOTARIUM.ic_box_m
    ax.add_patch(
        Rectangle((-box_x, -box_y), 2 * box_x, 2 * box_y, fill=False, ec='tab:blue', lw=0.6, ls='-.', label='start box')
    )
    ax.set_aspect('equal')
    ax.legend(loc='upper left', fontsize=7, ncols=3)
    ax.set_title(f'{scene.title} ({scene.swarm.n_robots} robots): {fit.reason}', fontsize=8, wrap=True)
    return fig
