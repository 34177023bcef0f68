"""Figures of `vtube_planning` objects. matplotlib is imported here only, when a figure is drawn (and by
`vtube_planning.geometry.occupancy` to read an obstacle image)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from vtube_planning.files import write_atomically

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from vtube_planning.geometry.obstacles import Obstacles
    from vtube_planning.geometry.occupancy import OccupancyImage
    from vtube_planning.geometry.scene import Scene
    from vtube_planning.geometry.tube import VirtualTube
    from vtube_planning.geometry.workspace import Workspace
    from vtube_planning.planning.plan import Plan
    from vtube_planning.swarm.simulate import SimResult


def draw_tube(ax: Axes, tube: VirtualTube, *, n_sections: int = 12, obstacles: Obstacles | None = None) -> None:
    """Draw a tube in the plane: filled interior, boundaries, centre line, cross-sections, entrance and exit, and
    the ``obstacles`` around it (grey)."""
    from matplotlib.patches import Circle
    from matplotlib.patches import Polygon as PolygonPatch

    discs = obstacles.discs if obstacles else ()
    polygons = obstacles.polygons if obstacles else ()
    for k, disc in enumerate(discs):
        label = 'obstacles' if k == 0 else None
        ax.add_patch(Circle(disc.center_m, disc.radius_m, color='0.55', alpha=0.8, lw=0, label=label))
    for k, polygon in enumerate(polygons):
        label = 'obstacles' if k == 0 and not discs else None
        ax.add_patch(PolygonPatch(np.array(polygon.vertices_m), color='0.55', alpha=0.8, lw=0, label=label))
    for k, image in enumerate(obstacles.images if obstacles else ()):
        _draw_image(ax, image, 'obstacles' if k == 0 and not (discs or polygons) else None)
    grid = np.linspace(0.0, tube.length_m, 1200)
    left, right = tube.boundaries(grid)
    center = tube.center_at(grid)
    outline = np.vstack([left, right[::-1]])
    ax.fill(outline[:, 0], outline[:, 1], color='tab:blue', alpha=0.12, lw=0)
    ax.plot(left[:, 0], left[:, 1], color='tab:blue', lw=1.5, label='boundaries')
    ax.plot(right[:, 0], right[:, 1], color='tab:blue', lw=1.5)
    ax.plot(center[:, 0], center[:, 1], color='0.3', lw=1.0, ls='--', label='centre line')
    sections = np.linspace(0.0, tube.length_m, n_sections + 1)
    sec_left, sec_right = tube.boundaries(sections)
    for k, (a, b) in enumerate(zip(sec_left, sec_right, strict=True)):
        end = k in (0, n_sections)
        color = ('tab:green' if k == 0 else 'tab:red') if end else '0.75'
        ax.plot([a[0], b[0]], [a[1], b[1]], color=color, lw=2.0 if end else 0.6)
    ax.set_aspect('equal')
    ax.set_xlabel('x [m]')
    ax.set_ylabel('y [m]')


UNKNOWN_RGBA = (0.85, 0.6, 0.25, 0.45)
"""The colour of an occupancy image's unknown cells (never mapped), whether they count as occupied or free."""


def _draw_image(ax: Axes, image: OccupancyImage, label: str | None) -> None:
    """Draw an occupancy image's occupied pixels (grey as the other obstacles; free pixels transparent) and its
    unknown cells (`UNKNOWN_RGBA`, labelled with what they count as), row 0 at the top of its extent, pixel for
    pixel."""
    from matplotlib.patches import Rectangle

    rgba = np.zeros((*image.occupied.shape, 4))
    rgba[image.occupied] = (0.55, 0.55, 0.55, 0.8)
    if image.unknown_cells is not None:
        rgba[image.unknown_cells] = UNKNOWN_RGBA
        counted = 'free' if image.unknown_free else 'occupied'
        ax.add_patch(Rectangle(image.origin_m, 0.0, 0.0, color=UNKNOWN_RGBA, lw=0, label=f'unknown cells ({counted})'))
    ax.imshow(rgba, extent=image.extent_m, origin='upper', interpolation='nearest', zorder=1)
    if label is not None:  # an image has no legend entry of its own
        ax.add_patch(Rectangle(image.origin_m, 0.0, 0.0, color='0.55', alpha=0.8, lw=0, label=label))


def scene_figure(scene: Scene) -> Figure:
    """The scene's tube in the plane, its half-width and its curvature along the arc length."""
    from matplotlib.figure import Figure

    tube = scene.tube
    fig = Figure(figsize=(10.0, 7.5), layout='constrained')
    grid_spec = fig.add_gridspec(2, 2, height_ratios=[1.6, 1.0])
    ax_plane = fig.add_subplot(grid_spec[0, :])
    draw_tube(ax_plane, tube, obstacles=scene.obstacles)
    if scene.workspace is not None:
        _draw_workspace(ax_plane, scene.workspace)
    ax_plane.legend(loc='best', fontsize=8)
    ax_plane.set_title(scene.title)

    grid = np.linspace(0.0, tube.length_m, 2000)
    lam = np.asarray(tube.half_width(grid))  # an array for an array of arc lengths
    breaks = np.unique(np.concatenate([tube.width.breakpoints, tube.center.breakpoints]))
    ax_width = fig.add_subplot(grid_spec[1, 0])
    ax_width.plot(grid, lam, color='tab:blue')
    ax_width.set_xlabel('arc length l [m]')
    ax_width.set_ylabel('half-width lambda(l) [m]')
    ax_width.set_ylim(0.0, 1.1 * float(lam.max()))

    ax_curv = fig.add_subplot(grid_spec[1, 1])
    ax_curv.fill_between(grid, -1.0 / lam, 1.0 / lam, color='tab:green', alpha=0.1, label='regular: |kappa| < 1/lambda')
    ax_curv.plot(grid, tube.curvature(grid), color='tab:orange', label='curvature kappa(l)')
    kappa_span = max(float(np.abs(tube.curvature(grid)).max()), 0.05 / float(lam.min()))
    ax_curv.set_ylim(-2.0 * kappa_span, 2.0 * kappa_span)
    ax_curv.set_xlabel('arc length l [m]')
    ax_curv.set_ylabel('curvature [1/m]')
    ax_curv.legend(loc='best', fontsize=8)
    for ax in (ax_width, ax_curv):
        for b in breaks:
            ax.axvline(b, color='0.85', lw=0.6, zorder=0)
        ax.set_xlim(0.0, tube.length_m)
    return fig


def _draw_workspace(ax: Axes, ws: Workspace) -> None:
    """Draw a scene's workspace and, dotted, the margin kept inside it."""
    from matplotlib.patches import Rectangle

    width, height = ws.x_max_m - ws.x_min_m, ws.y_max_m - ws.y_min_m
    ax.add_patch(Rectangle((ws.x_min_m, ws.y_min_m), width, height, fill=False, ec='k', lw=1.2, label='workspace'))
    m = ws.margin_m
    inner = (ws.x_min_m + m, ws.y_min_m + m)
    ax.add_patch(Rectangle(inner, width - 2 * m, height - 2 * m, fill=False, ec='k', lw=0.6, ls=':', label='margin'))


def plan_figure(plan: Plan) -> Figure:
    """v*(l) with its limits, rho*(l) with rho_d, the tube's half-width, and where each constraint binds."""
    from matplotlib.figure import Figure

    swarm = plan.swarm
    l = plan.l_m
    fine = np.linspace(0.0, plan.length_m, 10 * (l.size - 1) + 1)
    fig = Figure(figsize=(9.0, 8.0), layout='constrained')
    ax_v, ax_rho, ax_w, ax_act = fig.subplots(4, 1, sharex=True, height_ratios=[3, 3, 2, 1.4])
    ax_v.plot(fine, plan.speed(fine), color='tab:blue', lw=2, label='planned speed v*')
    ax_v.plot(
        l,
        np.minimum(plan.speed_limit_mps, 1.5 * swarm.v_max_mps),
        color='tab:orange',
        ls='--',
        label='curvature limit sqrt(a_n r_t)',
    )
    for value, name in ((swarm.v_min_mps, 'v_min'), (swarm.v_max_mps, 'v_max')):
        ax_v.axhline(value, color='0.5', lw=0.8, ls=':')
        ax_v.annotate(name, (plan.length_m, value), xytext=(2, 0), textcoords='offset points', fontsize=8, va='center')
    ax_v.set_ylim(0.0, 1.15 * swarm.v_max_mps)
    ax_v.set_ylabel('speed [m/s]')
    ax_v.legend(loc='lower right', fontsize=8)
    ax_v.set_title(
        f'plan for scene {plan.scene or "?"} ({plan.solved.method}): time {plan.time_s:.3f} s, '
        f'J = {plan.objective["total"]:.4f}, max violation {plan.max_violation:.1e}'
    )
    ax_rho.plot(fine, plan.density(fine), color='tab:green', lw=2, label='planned density rho*')
    ax_rho.axhline(swarm.rho_d_per_m2, color='tab:green', lw=0.8, ls=':', label='rho_d')
    ax_rho.set_ylim(0.0, 1.15 * float(plan.density_per_m2.max()))
    ax_rho.set_ylabel('density [1/m^2]')
    ax_rho.legend(loc='upper right', fontsize=8)
    ax_w.fill_between(l, -plan.half_width_m, plan.half_width_m, color='tab:blue', alpha=0.15)
    ax_w.plot(l, plan.half_width_m, color='tab:blue')
    ax_w.plot(l, -plan.half_width_m, color='tab:blue')
    ax_w.set_ylabel('half-width [m]')
    meaning = {
        'v_max': 'v_max',
        'v_min': 'v_min',
        'p3': '(p3) acceleration',
        'p4': '(p4) curvature',
        'p6': '(p6) expansion rate',
        'p7': '(p7) look-ahead',
    }
    names = [k for k in meaning if k in plan.active]
    for row, name in enumerate(names):
        mask = plan.active[name]
        ax_act.scatter(l[mask], np.full(int(mask.sum()), row), s=4, marker='s', color=f'C{row}')
    ax_act.set_yticks(range(len(names)), [meaning[n] for n in names], fontsize=8)
    ax_act.set_ylim(-0.7, len(names) - 0.3)
    ax_act.set_title('where each constraint binds (holds with equality)', fontsize=9)
    ax_act.set_xlabel('arc length l [m]')
    ax_act.set_xlim(0.0, plan.length_m)
    return fig


def snapshot_times(result: SimResult, count: int = 7) -> list[int]:
    """Indices of ``count`` steps evenly spread over the run."""
    return sorted({int(k) for k in np.linspace(0, result.t_s.size - 1, count)})


def snapshots_figure(result: SimResult, tube: VirtualTube, *, title: str = '') -> Figure:
    """The swarm at several instants over the tube, colour = time (the paper's kind of figure)."""
    from matplotlib import colormaps
    from matplotlib.collections import EllipseCollection
    from matplotlib.figure import Figure

    left, right = tube.boundaries(np.linspace(0.0, tube.length_m, 400))
    points = np.vstack([left, right, result.positions_m[snapshot_times(result)].transpose(0, 2, 1).reshape(-1, 2)])
    span = np.ptp(points, axis=0) + 1e-9
    fig = Figure(figsize=(10.0, float(np.clip(10.0 * span[1] / span[0] + 1.2, 2.8, 7.5))), layout='constrained')
    ax = fig.add_subplot()
    draw_tube(ax, tube)
    cmap = colormaps['viridis']
    steps = snapshot_times(result)
    t_end = float(result.t_s[-1]) or 1.0
    r_p = float(result.meta['swarm']['r_p_m'])
    label_y = float(points[:, 1].max()) + 2.0 * r_p  # the times in a row above everything drawn
    for k in steps:
        xy = result.positions_m[k].T
        color = cmap(float(result.t_s[k]) / t_end)
        ax.add_collection(
            EllipseCollection(
                np.full(len(xy), 2 * r_p),
                np.full(len(xy), 2 * r_p),
                0.0,
                units='xy',
                offsets=xy,
                offset_transform=ax.transData,
                facecolors=[color],
                edgecolors='k',
                linewidths=0.3,
            )
        )
        ax.annotate(
            f'{result.t_s[k]:.1f} s',
            (float(xy[:, 0].mean()), label_y),
            ha='center',
            va='bottom',
            fontsize=7,
            color=color,
        )
    ax.autoscale_view()
    low, high = ax.get_ylim()
    ax.set_ylim(low, max(high, label_y + 0.12 * (high - low)))
    mode = 'with planning' if result.planned else 'without planning'
    ax.set_title(
        title
        or f'swarm {mode}: passing time {result.metrics.passing_time_s:.2f} s, '
        f'min distance {result.metrics.min_distance_m:.3f} m'
    )
    return fig


def tracking_figure(result: SimResult, plan: Plan) -> Figure:
    """Average forward speed v_a against v* and measured density rho_r against rho*, along the swarm centre (the plan
    as flown, ``result.flown``, when the flight replanned)."""
    from matplotlib.figure import Figure

    center = result.l_m.mean(axis=1)
    inside = (center >= 0.0) & (center <= plan.length_m)
    fig = Figure(figsize=(9.0, 6.5), layout='constrained')
    ax_v, ax_rho, ax_ra = fig.subplots(3, 1, sharex=True, height_ratios=[3, 3, 2])
    grid = np.linspace(0.0, plan.length_m, 2000)
    flown = result.flown or plan.profile
    replanned = ' (as replanned)' if result.meta.get('replans') else ''
    ax_v.plot(grid, flown.speed(grid), color='tab:blue', ls='--', label=f'planned v*{replanned}')
    ax_v.plot(center[inside], result.forward_speed_mps.mean(axis=1)[inside], color='tab:blue', label='swarm v_a')
    ax_v.set_ylabel('speed [m/s]')
    ax_v.legend(fontsize=8)
    ax_rho.plot(grid, flown.density(grid), color='tab:green', ls='--', label=f'planned rho*{replanned}')
    ax_rho.plot(center[inside], result.density_per_m2[inside], color='tab:green', label='measured rho_r')
    ax_rho.set_ylabel('density [1/m^2]')
    ax_rho.legend(fontsize=8)
    ax_ra.plot(center[inside], result.r_a_m.mean(axis=1)[inside], color='tab:purple', label='mean r_a')
    ax_ra.fill_between(
        center[inside],
        result.r_a_m.min(axis=1)[inside],
        result.r_a_m.max(axis=1)[inside],
        color='tab:purple',
        alpha=0.2,
        label='range',
    )
    ax_ra.set_ylabel('r_a [m]')
    ax_ra.set_xlabel('arc length of the swarm centre [m]')
    ax_ra.legend(fontsize=8)
    ax_ra.set_xlim(0.0, plan.length_m)
    return fig


def distance_figure(results: dict[str, SimResult]) -> Figure:
    """Minimum inter-robot distance over time for one or more runs, with 2 r_p (collision) and 2 r_s marked."""
    from matplotlib.figure import Figure

    from vtube_planning.swarm.metrics import min_distance_over_time

    fig = Figure(figsize=(8.0, 3.8), layout='constrained')
    ax = fig.add_subplot()
    swarm = next(iter(results.values())).meta['swarm']
    for label, result in results.items():
        ax.plot(result.t_s, min_distance_over_time(result.positions_m), label=label)
    ax.axhline(2 * swarm['r_p_m'], color='tab:red', ls='--', label='2 r_p (collision)')
    ax.axhline(2 * swarm['r_s_m'], color='0.5', ls=':', label='2 r_s (safety)')
    ax.set_xlabel('time [s]')
    ax.set_ylabel('minimum distance [m]')
    ax.set_ylim(bottom=0.0)
    ax.legend(fontsize=8)
    return fig


GIF_WIDTH_PX = 1280
"""The GIF's width in pixels (a talk's slide); its height follows the framed scene's aspect."""


def animation_figure(result: SimResult, tube: VirtualTube) -> tuple[Figure, Callable[[int], tuple[Any, ...]]]:
    """The GIF's figure at the run's first step and a function that moves it to step ``k``: the tube and every
    robot's whole path framed with equal aspect and small margins, the robots as discs of radius r_p in data units
    (an ``EllipseCollection``), the time and the passage's measures in the title."""
    from matplotlib.collections import EllipseCollection
    from matplotlib.figure import Figure

    r_p = float(result.meta['swarm']['r_p_m'])
    left, right = tube.boundaries(np.linspace(0.0, tube.length_m, 400))
    paths = result.positions_m.transpose(0, 2, 1).reshape(-1, 2)
    points = np.vstack([left, right, paths[np.all(np.isfinite(paths), axis=1)]])
    low, high = points.min(axis=0) - r_p, points.max(axis=0) + r_p
    pad = np.maximum(0.03 * (high - low), 2 * r_p)  # per axis: a long tube keeps a thin margin beside it
    low, high = low - pad, high + pad
    width_in, (left_in, right_in, bottom_in, top_in) = GIF_WIDTH_PX / 100, (0.75, 0.2, 0.5, 0.4)  # at 100 dpi
    plot_w = width_in - left_in - right_in
    plot_h = plot_w * (high[1] - low[1]) / (high[0] - low[0])
    if plot_h < 1.2:  # a long, thin scene: more room above and below, not a squashed axis
        middle, half = 0.5 * (low[1] + high[1]), 0.5 * 1.2 * (high[0] - low[0]) / plot_w
        low[1], high[1], plot_h = middle - half, middle + half, 1.2
    elif plot_h > 7.0:  # a tall scene: narrower, centred
        plot_w, plot_h = plot_w * 7.0 / plot_h, 7.0
        left_in = 0.5 * (width_in - plot_w)
    height_in = plot_h + bottom_in + top_in
    fig = Figure(figsize=(width_in, height_in), dpi=100)
    ax = fig.add_axes((left_in / width_in, bottom_in / height_in, plot_w / width_in, plot_h / height_in))
    draw_tube(ax, tube)
    ax.set_xlim(low[0], high[0])
    ax.set_ylim(low[1], high[1])
    ax.set_aspect('equal', adjustable='box')
    n = result.positions_m.shape[2]
    discs = EllipseCollection(
        np.full(n, 2 * r_p),
        np.full(n, 2 * r_p),
        np.zeros(n),
        units='xy',
        offsets=result.positions_m[0].T,
        offset_transform=ax.transData,
        facecolors='tab:red',
        edgecolors='k',
        linewidths=0.4,
        zorder=3,
    )
    ax.add_collection(discs, autolim=False)
    mode = 'with planning' if result.planned else 'without planning'
    m = result.metrics
    said = f'{n} robots {mode} (discs of radius r_p = {r_p:g} m); passing time {m.passing_time_s:.1f} s'
    label = ax.set_title('')

    def update(k: int) -> tuple[Any, ...]:
        discs.set_offsets(result.positions_m[k].T)
        label.set_text(f'{said}; t = {result.t_s[k]:.1f} s')
        return discs, label

    update(0)
    return fig, update


def animate(
    result: SimResult,
    tube: VirtualTube,
    path: str | Path,
    *,
    frames: int = 120,
    fps: int = 15,
    progress: Callable[[int, int], None] | None = None,
) -> Path:
    """Write an animated GIF of the run (`animation_figure`, ``frames`` steps evenly spread over the run, at
    ``fps``; matplotlib's Pillow writer, no external encoder); ``progress(i, n)`` is told each frame written."""
    from matplotlib.animation import FuncAnimation, PillowWriter

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, update = animation_figure(result, tube)
    steps = np.unique(np.linspace(0, result.t_s.size - 1, frames).astype(int))
    animation = FuncAnimation(fig, update, frames=steps, blit=False)
    animation.save(path, writer=PillowWriter(fps=fps), dpi=100, progress_callback=progress)
    return path


def save_figure(fig: Figure, path: str | Path, *, dpi: int = 120) -> Path:
    """Write a figure (atomically, `write_atomically`); returns the path written."""
    path = Path(path)
    return write_atomically(path, lambda handle: fig.savefig(handle, dpi=dpi, format=path.suffix[1:] or 'png'))
