"""Figures of analysed trajectories (paths, tracking, distances). matplotlib is imported when a figure is drawn.

They draw what :func:`robotarium_exp.analysis.report.analyse` computed (nothing is measured twice); lines break
where a robot has no position. Without a scene there is no tube to draw and no tracking figure.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from vtube_planning.plots import draw_tube

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from robotarium_exp.analysis.report import Analysis
    from vtube_planning.geometry.scene import Scene
    from vtube_planning.planning.plan import Plan


def analysis_figures(results: dict[str, Analysis], scene: Scene | None, plan: Plan | None) -> dict[str, Figure]:
    """Paths with snapshots (one panel per source), tracking along l (with a scene), minimum distance over time."""
    from matplotlib import colormaps
    from matplotlib.figure import Figure

    figures = {}
    paths = Figure(figsize=(8.0, 3.6 * len(results)), layout='constrained')
    cmap = colormaps['viridis']
    for ax, (label, a) in zip(np.atleast_1d(paths.subplots(len(results), 1)), results.items(), strict=True):
        if scene is not None:
            draw_tube(ax, scene.tube, n_sections=8)
        p, t = a.trajectory.positions_m, a.trajectory.t_s
        for k in range(p.shape[2]):
            ax.plot(p[:, 0, k], p[:, 1, k], color='0.6', lw=0.6)
        for step in np.unique(np.linspace(0, t.size - 1, 7).astype(int)):
            ax.scatter(*p[step], s=25, color=cmap(step / max(1, t.size - 1)), edgecolors='k', linewidths=0.3, zorder=3)
        ax.set_aspect('equal')
        ax.set_title(f'{label}: paths, snapshots coloured by time')
    figures['paths'] = paths
    if scene is not None:
        tracking = Figure(figsize=(8.0, 5.5), layout='constrained')
        ax_v, ax_rho = tracking.subplots(2, 1, sharex=True)
        for label, a in results.items():
            if a.along is None:
                continue
            d = a.along
            center = d.l_m[d.complete].mean(axis=1)
            inside = (center >= 0) & (center <= scene.tube.length_m)
            ax_v.plot(center[inside], d.forward_speed_mps[d.complete].mean(axis=1)[inside], label=f'{label}: v_a')
            ax_rho.plot(center[inside], d.density_per_m2[d.complete][inside], label=f'{label}: rho_r')
        if plan is not None:
            grid = np.linspace(0.0, plan.length_m, 1000)
            ax_v.plot(grid, plan.speed(grid), 'k--', label='plan v*')
            ax_rho.plot(grid, plan.density(grid), 'k--', label='plan rho*')
        ax_v.set_ylabel('speed along the tube [m/s]')
        ax_rho.set_ylabel('density [1/m^2]')
        ax_rho.set_xlabel('arc length of the swarm centre [m]')
        for ax in (ax_v, ax_rho):
            ax.legend(fontsize=8)
        figures['tracking'] = tracking
    distance = Figure(figsize=(8.0, 3.5), layout='constrained')
    ax = distance.add_subplot()
    for label, a in results.items():
        ax.plot(a.trajectory.t_s, a.distances.frame_min_m, label=label)
    collision = next((a.metrics['collision_distance_m'] for a in results.values()), None)
    if collision is not None:
        ax.axhline(collision, color='tab:red', ls='--', label='collision distance')
    ax.set_xlabel('time [s]')
    ax.set_ylabel('minimum distance [m]')
    ax.legend(fontsize=8)
    figures['distance'] = distance
    return figures
