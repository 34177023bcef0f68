"""Figures of Robotarium experiments. matplotlib is imported here only, when a figure is drawn."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.plots import draw_tube

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from robotarium_exp.experiment import ExperimentResult
    from vtube_planning.geometry.scene import Scene
    from vtube_planning.planning.plan import Plan


def experiment_figure(result: ExperimentResult, scene: Scene, plan: Plan | None = None) -> Figure:
    """The arena with the tube, robot paths and snapshots (colour = time); r_a and density over time."""
    from matplotlib import colormaps
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle, Rectangle

    arrays = result.arrays
    t = arrays['t_s']
    fig = Figure(figsize=(9.0, 8.0), layout='constrained')
    ax, ax_ra = fig.subplots(2, 1, height_ratios=[2.2, 1])
    draw_tube(ax, scene.tube, n_sections=8)
    xmin, xmax, ymin, ymax = ROBOTARIUM.arena_m
    ax.add_patch(Rectangle((xmin, ymin), xmax - xmin, ymax - ymin, fill=False, ec='k', lw=1.2))
    cmap = colormaps['viridis']
    poses = arrays['positions_m']
    for k in range(poses.shape[2]):
        ax.plot(poses[:, 0, k], poses[:, 1, k], color='0.6', lw=0.6)
    for step in np.unique(np.linspace(0, t.size - 1, 7).astype(int)):
        color = cmap(step / max(1, t.size - 1))
        for k in range(poses.shape[2]):
            center = (float(poses[step, 0, k]), float(poses[step, 1, k]))
            ax.add_patch(Circle(center, 0.055, fc=color, ec='k', lw=0.4, zorder=3))
        ax.annotate(
            f'{t[step]:.0f} s',
            poses[step, :2].mean(axis=1),
            xytext=(0, 16),
            textcoords='offset points',
            ha='center',
            fontsize=7,
            color=color,
        )
    ax.set_xlim(xmin - 0.1, xmax + 0.1)
    ax.set_ylim(ymin - 0.1, ymax + 0.1)
    e, m = result.errors, result.metrics
    ax.set_title(
        f'{scene.name}, {"with" if result.meta["planned"] else "without"} planning: '
        f'{e.get("robots_too_close", 0)} too close, {e.get("robots_outside_boundaries", 0)} outside, '
        f'{e.get("exceeded_actuator_limits", 0)} actuator; min distance {m.min_distance_m:.3f} m'
    )
    ra = arrays['r_a_m']
    ax_ra.plot(t, ra.mean(axis=1), color='tab:purple', label='mean r_a [m]')
    ax_ra.fill_between(t, ra.min(axis=1), ra.max(axis=1), color='tab:purple', alpha=0.2)
    ax_ra.set_xlabel('time [s]')
    ax_ra.set_ylabel('r_a [m]')
    ax_rho = ax_ra.twinx()
    ax_rho.plot(t, arrays['density_per_m2'], color='tab:green', label='measured density')
    if plan is not None:
        ax_rho.plot(t, plan.density(arrays['l_m'].mean(axis=1)), color='tab:green', ls='--', label='planned density')
    ax_rho.set_ylabel('density [1/m^2]')
    ax_ra.legend(loc='upper left', fontsize=8)
    ax_rho.legend(loc='upper right', fontsize=8)
    return fig
