"""Figures of Robotarium experiments. matplotlib is imported here only, when a figure is drawn."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.plots import draw_tube

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from numpy.typing import NDArray

    from robotarium_exp.experiment import ExperimentResult
    from robotarium_exp.fit import Fit
    from vtube_planning.geometry.scene import Scene
    from vtube_planning.planning.plan import Plan


def experiment_figure(result: ExperimentResult, scene: Scene, plan: Plan | None = None) -> Figure:
    """The paper's Robotarium figure: the arena with the tube, paths and snapshots (colour = time, on a colour bar)
    with every robot's avoidance radius drawn; below, over the time robots fly the tube, the planned and measured
    density and r_a while every robot flies, and the robots' forward speed (median and range over those still
    flying), with the moment the expansion starts, the moment the front reaches the narrowing and, where a curve
    ends, why."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 10.5), layout='constrained')
    ax, ax_rho, ax_v = fig.subplots(3, 1, height_ratios=[2.2, 1, 1], sharex=False)
    _arena_panel(ax, result, scene)
    _time_panels(ax_rho, ax_v, result, scene, plan)
    return fig


SNAPSHOTS = 7
"""Snapshots of the robots in the arena panel, evenly spread in time."""


def _arena_panel(ax: Axes, result: ExperimentResult, scene: Scene) -> None:
    """The arena, the tube, the paths and seven snapshots of the robots with their avoidance radii; the snapshots'
    times on a colour bar (not beside the robots: parked robots' snapshots stand on one another)."""
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize
    from matplotlib.patches import Circle, Rectangle

    arrays = result.arrays
    t = arrays['t_s']
    draw_tube(ax, scene.tube, n_sections=8, obstacles=scene.obstacles)
    xmin, xmax, ymin, ymax = ROBOTARIUM.arena_m
    ax.add_patch(Rectangle((xmin, ymin), xmax - xmin, ymax - ymin, fill=False, ec='k', lw=1.2))
    cmap, norm = colormaps['viridis'], Normalize(float(t[0]), max(float(t[-1]), float(t[0]) + 1e-9))
    poses = arrays['positions_m']
    for k in range(poses.shape[2]):
        ax.plot(poses[:, 0, k], poses[:, 1, k], color='0.6', lw=0.6)
    steps = np.unique(np.linspace(0, t.size - 1, SNAPSHOTS).astype(int))
    for step in steps:
        color = cmap(norm(t[step]))
        for k in range(poses.shape[2]):
            center = (float(poses[step, 0, k]), float(poses[step, 1, k]))
            ax.add_patch(Circle(center, 0.5 * ROBOTARIUM.robot_diameter_m, fc=color, ec='k', lw=0.4, zorder=3))
            if arrays['flying'][step, k]:
                radius = float(arrays['r_a_m'][step, k])
                ax.add_patch(Circle(center, radius, fill=False, ec=color, lw=0.6, ls='--', zorder=2))
    spacing = float(np.min(np.diff(t[steps]))) if steps.size > 1 else 1.0
    bar = ax.figure.colorbar(ScalarMappable(norm, cmap), ax=ax, shrink=0.85, pad=0.02, ticks=t[steps])
    bar.ax.set_yticklabels([f'{t[s]:.{0 if spacing >= 2 else 1 if spacing >= 0.2 else 2}f}' for s in steps])
    bar.set_label('snapshot time [s]')
    ax.set_xlim(xmin - 0.1, xmax + 0.1)
    ax.set_ylim(ymin - 0.1, ymax + 0.1)
    ax.set_aspect('equal')
    e, m, n = result.errors, result.metrics, poses.shape[2]
    closest = f'min distance {m.min_distance_m:.3f} m' if np.isfinite(m.min_distance_m) else 'no two robots'
    ax.set_title(
        f'{scene.name} ({n} robot{"s" if n != 1 else ""}), {"with" if result.planned else "without"} planning: '
        f'{e.too_close} too close, {e.outside} outside, {e.actuator} actuator;\n{closest};'
        " dashed circles: each robot's avoidance radius r_a",
        fontsize=10,
    )


def _time_panels(ax_rho: Axes, ax_v: Axes, result: ExperimentResult, scene: Scene, plan: Plan | None) -> None:
    """Over the time any robot flies the tube: density and mean r_a, planned and measured, while every robot flies
    (the swarm's measures), and the forward speed of the robots still flying (median, min-max band) with the
    planned speed; the moments the expansion starts and the front reaches the narrowing; where the swarm's curves
    end (a robot parks), shaded and said; a panel with nothing to draw says why."""
    from robotarium_exp.tracking import expansion_times

    arrays = result.arrays
    t, flying = arrays['t_s'], arrays['flying'].astype(bool)
    whole = np.cumprod(flying.all(axis=1)).astype(bool)  # every robot flies, from the start on
    center = arrays['l_m'].mean(axis=1)
    ax_rho.plot(t[whole], arrays['density_per_m2'][whole], color='tab:green', label='measured density')
    if plan is not None:
        ax_rho.plot(t[whole], plan.density(center[whole]), color='tab:green', ls='--', label='planned density')
        ax_v.plot(t[whole], plan.speed(center[whole]), color='tab:blue', ls='--', label='planned speed')
    ax_ra = ax_rho.twinx()
    ax_ra.plot(t[whole], arrays['r_a_m'].mean(axis=1)[whole], color='tab:purple', label='mean r_a')
    ax_ra.set_ylabel('r_a [m]')
    end_s = _speed_band(ax_v, t, arrays['dxu'][:, 0, :], flying)
    expansion_s, narrowing_s = expansion_times(arrays, scene)
    for axis in (ax_rho, ax_v):
        if expansion_s is not None:
            axis.axvline(expansion_s, color='tab:purple', ls=':', lw=1.0, label='expansion starts')
        if narrowing_s is not None:
            axis.axvline(narrowing_s, color='k', ls=':', lw=1.0, label='front reaches the narrowing')
        axis.set_xlim(float(t[0]), float(t[0]) + 1.02 * max(end_s - float(t[0]), 1e-3))
        axis.set_xlabel('time [s]')
    _say_where_curves_end(ax_rho, ax_v, t, flying, whole, result.completed)
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
    ax_v.set_ylabel('forward speed [m/s]')


def _speed_band(ax: Axes, t: NDArray[np.float64], forward: NDArray[np.float64], flying: NDArray[np.bool_]) -> float:
    """The forward speed of the robots flying at each step, median and min-max band, drawn as far as any robot
    flies; returns the time of that step (the run's last when none ever flies)."""
    rows = flying.any(axis=1)
    if not rows.any():
        return float(t[-1])
    last = int(np.flatnonzero(rows)[-1])
    speeds = np.where(flying[rows], forward[rows], np.nan)
    many = flying.shape[1] > 1
    ax.plot(
        t[rows],
        np.nanmedian(speeds, axis=1),
        color='tab:blue',
        label='median of the robots flying' if many else 'forward speed',
    )
    if many:
        low, high = np.nanmin(speeds, axis=1), np.nanmax(speeds, axis=1)
        ax.fill_between(t[rows], low, high, color='tab:blue', alpha=0.2, lw=0, label='their min-max')
    return float(t[last])


def _say_where_curves_end(
    ax_rho: Axes,
    ax_v: Axes,
    t: NDArray[np.float64],
    flying: NDArray[np.bool_],
    whole: NDArray[np.bool_],
    completed: bool,
) -> None:
    """Shade the time after the first robot parks and say there why the swarm's curves end; say so in a panel
    that has nothing to draw, and say when the run stopped with robots still flying."""
    if not flying.any():
        for axis in (ax_rho, ax_v):
            _centred(axis, 'no robot flies the tube in this run')
        return
    if not whole.all():
        cut = int(np.argmin(whole))
        robot = int(np.flatnonzero(~flying[cut])[0])
        said = [f"robot {robot} parks at {t[cut]:.1f} s:\nthe swarm's density, r_a and plan end"]
        if flying[cut:].any():
            said.append(f'from {t[cut]:.1f} s: the robots still flying')
        low, high = ax_v.get_xlim()
        right = t[cut] < 0.6 * (high - low) + low  # the text on the side of the line with room
        for axis, text in zip((ax_rho, ax_v), said, strict=False):
            axis.axvspan(float(t[cut]), high, color='0.9', lw=0, zorder=0)
            axis.text(float(t[cut]), 0.97, f' {text} ' if right else f'{text} ', ha='left' if right else 'right',
                      va='top', fontsize=7, transform=axis.get_xaxis_transform(),
                      bbox={'fc': 'w', 'alpha': 0.7, 'lw': 0, 'pad': 1})  # fmt: skip
        if cut == 0:
            _centred(ax_rho, f'robot {robot} is parked from the start: no step with every robot flying')
    if not completed and flying[-1].any():
        ax_v.text(float(t[-1]), 0.03, f'run stopped, {int(flying[-1].sum())} robot(s) flying ', ha='right',
                  va='bottom', fontsize=7, transform=ax_v.get_xaxis_transform())  # fmt: skip


def _centred(ax: Axes, text: str) -> None:
    ax.text(0.5, 0.5, text, ha='center', va='center', fontsize=9, transform=ax.transAxes)


def scene_figure(scene: Scene, fit: Fit) -> Figure:
    """The scene's figure (`vtube_planning.plots.scene_figure`) with what the Robotarium adds: the start
    formation (bodies, and the interaction band r_s + r_a dashed), the parking slots, the box the testbed
    initializes robots in, and the fit verdict in the title."""
    from matplotlib.patches import Circle, Rectangle

    from robotarium_exp.design import start_formation
    from robotarium_exp.parking_slots import parking
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
