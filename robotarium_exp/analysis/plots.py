"""Figures of analysed trajectories (paths, tracking, distances). matplotlib is imported when a figure is drawn."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from vtube_planning.plots import draw_tube

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from vtube_planning.geometry.scene import Scene
    from vtube_planning.planning.plan import Plan


def analysis_figures(results: dict, scene: Scene, plan: Plan | None) -> dict[str, Figure]:
    """Paths over the tube with snapshots (one panel per source), tracking along l, minimum distance over time."""
    from matplotlib import colormaps
    from matplotlib.figure import Figure

    from robotarium_exp.analysis.report import along_tube
    from vtube_planning.swarm.metrics import min_distance_over_time

    data = {label: along_tube(traj, scene) for label, (traj, _) in results.items()}
    paths = Figure(figsize=(8.0, 3.6 * len(data)), layout='constrained')
    cmap = colormaps['viridis']
    for ax, (label, d) in zip(np.atleast_1d(paths.subplots(len(data), 1)), data.items(), strict=True):
        draw_tube(ax, scene.tube, n_sections=8)
        p, t = d['positions_m'], d['t_s']
        for k in range(p.shape[2]):
            ax.plot(p[:, 0, k], p[:, 1, k], color='0.6', lw=0.6)
        for step in np.unique(np.linspace(0, t.size - 1, 7).astype(int)):
            ax.scatter(*p[step], s=25, color=cmap(step / max(1, t.size - 1)), edgecolors='k', linewidths=0.3, zorder=3)
        ax.set_title(f'{label}: paths, snapshots coloured by time')
    tracking = Figure(figsize=(8.0, 5.5), layout='constrained')
    ax_v, ax_rho = tracking.subplots(2, 1, sharex=True)
    for label, d in data.items():
        center = d['l_m'].mean(axis=1)
        inside = (center >= 0) & (center <= scene.tube.length_m)
        ax_v.plot(center[inside], d['forward_speed_mps'].mean(axis=1)[inside], label=f'{label}: v_a')
        ax_rho.plot(center[inside], d['density_per_m2'][inside], label=f'{label}: rho_r')
    if plan is not None:
        grid = np.linspace(0.0, plan.length_m, 1000)
        ax_v.plot(grid, plan.speed(grid), 'k--', label='plan v*')
        ax_rho.plot(grid, plan.density(grid), 'k--', label='plan rho*')
    ax_v.set_ylabel('speed along the tube [m/s]')
    ax_rho.set_ylabel('density [1/m^2]')
    ax_rho.set_xlabel('arc length of the swarm centre [m]')
    for ax in (ax_v, ax_rho):
        ax.legend(fontsize=8)
    distance = Figure(figsize=(8.0, 3.5), layout='constrained')
    ax = distance.add_subplot()
    for label, d in data.items():
        ax.plot(d['t_s'], min_distance_over_time(d['positions_m']), label=label)
    ax.axhline(2 * scene.swarm.r_p_m, color='tab:red', ls='--', label='2 r_p')
    ax.set_xlabel('time [s]')
    ax.set_ylabel('minimum distance [m]')
    ax.legend(fontsize=8)
    return {'paths': paths, 'tracking': tracking, 'distance': distance}
