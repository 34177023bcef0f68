"""Figures of analysed trajectories (paths, tracking, distances). matplotlib is imported when a figure is drawn.

They draw what [`robotarium_exp.analysis.report.analyse`][robotarium_exp.analysis.report.analyse] computed (nothing is
measured twice); lines break where a robot has no position. Without a scene there is no tube to draw and no tracking
figure.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from vtube_planning.plots import draw_tube

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from robotarium_exp.analysis.metrics import Analysis
    from robotarium_exp.analysis.trajectory import Trajectory
    from vtube_planning.geometry.scene import Scene
    from vtube_planning.planning.plan import Plan


DRAWN_FRAMES = 100_000
"""Frames drawn in a line at most (more than a figure has pixels): a longer recording is thinned to every k-th frame
for its paths (frames where a robot has no position kept, so that lines still break there) and to each block's
smallest value for the minimum distance (so that no close approach is hidden)."""
SOURCES = {'data': 'the recording analysed', 'comparison': 'the simulation given with --compare'}
"""What each source of a report is, in the figures' titles and legends."""


def _named(label: str) -> str:
    return f'{label} ({SOURCES[label]})' if label in SOURCES else label


def analysis_figures(results: dict[str, Analysis], scene: Scene | None, plan: Plan | None) -> dict[str, Figure]:
    """Paths with snapshots, tracking along l (with a scene), minimum distance over time."""
    figures = {'paths': _paths_figure(results, scene)}
    if scene is not None:
        figures['tracking'] = _tracking_figure(results, scene, plan)
    figures['distance'] = _distance_figure(results)
    return figures


def _paths_figure(results: dict[str, Analysis], scene: Scene | None) -> Figure:
    """One panel per source, on the same axes, robots at seven instants coloured by time (a colour bar): instants
    spread over the time every robot is recorded (`Trajectory.common_span`), each robot at its position at
    that instant (`Trajectory.positions_at`); a robot without one is named in the title."""
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure

    cmap = colormaps['viridis']
    t_end = max(float(a.trajectory.t_s[-1]) for a in results.values()) or 1.0
    thinned = {label: a.trajectory.positions_m[_drawn(a.trajectory)] for label, a in results.items()}
    drawn = [p.transpose(0, 2, 1).reshape(-1, 2) for p in thinned.values()]
    if scene is not None:
        drawn += list(scene.tube.boundaries(np.linspace(0.0, scene.tube.length_m, 200)))
    points = np.vstack(drawn)
    points = points[np.all(np.isfinite(points), axis=1)]
    low, high = points.min(axis=0), points.max(axis=0)
    pad = 0.05 * max(float(np.max(high - low)), 1e-3)
    low, high = low - pad, high + pad  # every panel on the same axes: the sources compare by eye
    panel_h = float(np.clip(7.0 * (high[1] - low[1]) / (high[0] - low[0]), 1.2, 6.0)) + 0.9
    paths = Figure(figsize=(9.0, panel_h * len(results) + 0.3), layout='constrained')
    axes = np.atleast_1d(paths.subplots(len(results), 1))
    for ax, (label, a) in zip(axes, results.items(), strict=True):
        if scene is not None:
            draw_tube(ax, scene.tube, n_sections=8, obstacles=scene.obstacles)
        for k in range(a.trajectory.n_robots):
            ax.plot(thinned[label][:, 0, k], thinned[label][:, 1, k], color='0.6', lw=0.6)
        missing = []
        for when in np.linspace(*a.trajectory.common_span(), 7):
            at = a.trajectory.positions_at(float(when))
            ax.scatter(*at, s=25, color=cmap(when / t_end), edgecolors='k', linewidths=0.3, zorder=3)
            absent = [rid for rid, seen in zip(a.trajectory.robot_ids, np.isfinite(at[0]), strict=True) if not seen]
            if absent:
                missing.append(f'{when:.1f} s: {", ".join(absent[:4])}{" ..." if len(absent) > 4 else ""}')
        ax.set_xlim(low[0], high[0])
        ax.set_ylim(low[1], high[1])
        ax.set_aspect('equal')
        note = f'\nno position (gap or outside its recording) at {"; ".join(missing)}' if missing else ''
        ax.set_title(f'{_named(label)}: paths, robots at seven instants{note}', fontsize=10)
    paths.colorbar(ScalarMappable(Normalize(0.0, t_end), cmap), ax=list(axes), label='time [s]', shrink=0.8)
    return paths


def _drawn(trajectory: Trajectory) -> NDArray[np.bool_]:
    """The frames of ``trajectory`` drawn in its paths (`DRAWN_FRAMES`)."""
    drawn = np.zeros(trajectory.t_s.size, dtype=bool)
    drawn[:: -(-trajectory.t_s.size // DRAWN_FRAMES)] = True
    drawn[-1] = True
    drawn |= ~trajectory.complete_frames()
    return drawn


def _tracking_figure(results: dict[str, Analysis], scene: Scene, plan: Plan | None) -> Figure:
    """Mean forward speed and density against the swarm centre's arc length, and the plan's."""
    from matplotlib.figure import Figure

    tracking = Figure(figsize=(8.0, 5.5), layout='constrained')
    ax_v, ax_rho = tracking.subplots(2, 1, sharex=True)
    for label, a in results.items():
        if a.along is None:
            continue
        d = a.along
        center = d.l_m[d.complete].mean(axis=1)
        inside = (center >= 0) & (center <= scene.tube.length_m)
        speed = d.forward_speed_mps[d.complete].mean(axis=1)[inside]
        ax_v.plot(center[inside], speed, label=_named(label))
        ax_rho.plot(center[inside], d.density_per_m2[d.complete][inside], label=_named(label))
    if plan is not None:
        grid = np.linspace(0.0, plan.length_m, 1000)
        ax_v.plot(grid, plan.speed(grid), 'k--', label='the plan (v*, rho*)')
        ax_rho.plot(grid, plan.density(grid), 'k--')
    ax_v.set_ylabel('speed along the tube [m/s]')
    ax_rho.set_ylabel('density [1/m^2]')
    ax_rho.set_xlabel('arc length of the swarm centre [m]')
    tracking.legend(*ax_v.get_legend_handles_labels(), loc='outside lower center', ncols=3, fontsize=8)
    for ax in (ax_v, ax_rho):
        ax.ticklabel_format(axis='y', useOffset=False)  # a flat line stays flat, not 1e-14 noise magnified
        low, high = ax.get_ylim()
        middle, half = 0.5 * (low + high), max(0.5 * (high - low), 0.05 * abs(0.5 * (low + high)), 1e-6)
        ax.set_ylim(middle - half, middle + half)
    return tracking


def _distance_figure(results: dict[str, Analysis]) -> Figure:
    """The smallest distance between two robots over time, and the collision distance."""
    from matplotlib.figure import Figure

    distance = Figure(figsize=(8.0, 3.5), layout='constrained')
    ax = distance.add_subplot()
    for label, a in results.items():
        starts = np.arange(0, a.trajectory.t_s.size, -(-a.trajectory.t_s.size // DRAWN_FRAMES))
        ax.plot(a.trajectory.t_s[starts], np.fmin.reduceat(a.distances.frame_min_m, starts), label=_named(label))
    collision = next((a.metrics.collision_distance_m for a in results.values()), None)
    if collision is not None:
        ax.axhline(collision, color='tab:red', ls='--', label='collision distance')
    ax.set_xlabel('time [s]')
    ax.set_ylabel('minimum distance [m]')
    ax.legend(fontsize=8)
    return distance
