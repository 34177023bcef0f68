"""Figures of :mod:`vtube_planning` objects. matplotlib is imported here only, when a figure is drawn."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from vtube_planning.scene import Scene
    from vtube_planning.tube import VirtualTube


def draw_tube(ax: Axes, tube: VirtualTube, *, n_sections: int = 12) -> None:
    """Draw a tube in the plane: filled interior, boundaries, centre line, cross-sections, entrance and exit."""
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


def scene_figure(scene: Scene) -> Figure:
    """The scene's tube in the plane, its half-width and its curvature along the arc length."""
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    tube = scene.tube
    fig = Figure(figsize=(10.0, 7.5), layout='constrained')
    grid_spec = fig.add_gridspec(2, 2, height_ratios=[1.6, 1.0])
    ax_plane = fig.add_subplot(grid_spec[0, :])
    draw_tube(ax_plane, tube)
    ws = scene.workspace
    if ws is not None:
        ax_plane.add_patch(
            Rectangle((ws.x_min_m, ws.y_min_m), ws.x_max_m - ws.x_min_m, ws.y_max_m - ws.y_min_m,
                      fill=False, ec='k', lw=1.2, label='workspace')
        )
        m = ws.margin_m
        ax_plane.add_patch(
            Rectangle((ws.x_min_m + m, ws.y_min_m + m), ws.x_max_m - ws.x_min_m - 2 * m,
                      ws.y_max_m - ws.y_min_m - 2 * m, fill=False, ec='k', lw=0.6, ls=':', label='margin')
        )
    ax_plane.legend(loc='best', fontsize=8)
    ax_plane.set_title(scene.title)

    grid = np.linspace(0.0, tube.length_m, 2000)
    lam = tube.half_width(grid)
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


def save_figure(fig: Figure, path: str | Path, *, dpi: int = 120) -> Path:
    """Write a figure, creating the folder; returns the path written."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    return path
