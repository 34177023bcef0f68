"""A run as one offline HTML page that plays it (``vtube replay``): the tube, the robots to scale, their trails, and
the planned and measured density and speed over time with a cursor at the drawn frame.

The technology: a hand-written page (``replay.html``, package data) that draws on a canvas from the run's numbers,
embedded as JSON. No dependency, and the file grows with the numbers only (some 17 bytes per robot and frame: its
position and r_a). The alternatives lost: matplotlib's ``to_jshtml`` embeds one PNG per frame (tens of kilobytes
each: tens of megabytes for a minute at 30 frames a second) and cannot move a cursor in other panels with its
slider; plotly is not a dependency and would add several megabytes of JavaScript (plotly.min.js) to every file, or
a network fetch where the page is meant to work offline.

What is embedded: the frames a browser plays smoothly (`playback_frames`: at most `MAX_FPS` per second
of the run), coordinates in whole millimetres (`millimetres`; NaN, a robot without a position, is null),
the tube's centre line and walls, the obstacles' outlines, the radii r_p and r_a (each robot's recorded r_a per
frame when a vtube log holds it, `recorded_avoidance_radii`, else the scene's), and the panels
(`panels`). Text from the loaded files (paths, robot ids, the scene's title) enters the page only inside
that JSON (``json.dumps`` with ``<``, ``>`` and ``&`` escaped, `embed`: no string can close the script
element) or HTML-escaped in the ``<title>``; the page reads the JSON with ``JSON.parse`` and shows text with
``textContent``. The page sets its slider from a fragment (``run.html#t=30``: the last frame at or before 30 s;
``&play`` starts playing) through the slider's own input handler, and writes the drawn frame (its index, time,
whether it plays and the robots' centres) into ``<pre id="state">``.
"""

from __future__ import annotations

import html
import json
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotarium_exp.analysis.passage import along_tube
from robotarium_exp.analysis.trajectory import Trajectory
from robotarium_exp.errors import AnalysisError
from vtube_planning.errors import LogError
from vtube_planning.files import write_atomically
from vtube_planning.geometry.scene import Scene
from vtube_planning.log import read_log
from vtube_planning.planning.plan import Plan

FloatArray = NDArray[np.float64]

MAX_FPS = 30
"""Frames per second of the run embedded at most: one per 1/MAX_FPS s bin of time (`playback_frames`)."""
TRAIL_S = 2.0
"""The length of each robot's trail, in seconds of the run."""
TUBE_POINTS = 400
"""Points along the tube's centre line and walls."""
TEMPLATE = 'replay.html'
TITLE_MARK, DATA_MARK = '__REPLAY_TITLE__', '__REPLAY_DATA__'
LOG_ROBOT = 'robot_'
"""The prefix of a vtube log's robot ids (`robotarium_exp.analysis.loaders`): the log's column follows it."""


@dataclass(frozen=True)
class Replay:
    """A replay written: the file, its size, the frames embedded, the frames in the run, the robots and the run's duration."""

    out: Path
    size_bytes: int
    frames: int
    frames_in_run: int
    robots: int
    duration_s: float


def check_page(out: Path) -> None:
    """Refuse, before any work, a page that would not open as one: a name not ending in .html, or a folder."""
    if out.suffix.lower() not in ('.html', '.htm') or out.is_dir():
        msg = f'{out} is not an .html file; give --out a name ending in .html (the replay is one web page).'
        raise AnalysisError(msg)


def replayed_scene(trajectory: Trajectory, given: str | None) -> str:
    """The scene to replay ``trajectory`` in: ``given``, else the one its log records; refused without either."""
    name = given if given is not None else trajectory.source.get('scene')
    if not name:
        msg = (
            f'{trajectory.source.get("path", "the run")} records no scene, and the replay draws the tube: give the '
            'scene it was recorded in with --scene (a name from vtube scene list, or a .toml file).'
        )
        raise AnalysisError(msg)
    return str(name)


def flew_a_plan(trajectory: Trajectory) -> bool:
    """Whether the plan is shown beside the measures: unless the log records a run without one (--no-planning)."""
    return trajectory.source.get('planned') is not False


def plan_label(plan_file: Path | None) -> str:
    """The plan's name in the panels: the file given, or the scene's plan computed again (as vtube plan does)."""
    return f'the plan {plan_file.name}' if plan_file is not None else "the scene's plan (computed as vtube plan does)"


def playback_frames(t_s: ArrayLike, max_fps: float = MAX_FPS) -> NDArray[np.int64]:
    """The frames kept: the first frame of each bin [k / max_fps, (k + 1) / max_fps) of time that holds one (a
    frame within 1e-6 of a bin's start counts in it: times read from files are rounded)."""
    bins = np.floor(np.asarray(t_s, dtype=float) * max_fps + 1e-6)
    kept = np.concatenate([[True], np.diff(bins) > 0])
    return np.flatnonzero(kept).astype(np.int64)


def millimetres(values_m: ArrayLike) -> list[Any]:
    """Metres as whole millimetres, nested as the array is; NaN as None (JSON null)."""
    values = np.asarray(values_m, dtype=float)
    finite = np.isfinite(values)
    whole = np.where(finite, np.round(values * 1000.0), 0.0).astype(np.int64).astype(object)
    whole[~finite] = None
    listed: list[Any] = whole.tolist()
    return listed


def _rounded(values: ArrayLike, digits: int = 4) -> list[float | None]:
    """Values rounded to ``digits`` significant digits; NaN as None."""
    return [float(f'{v:.{digits}g}') if math.isfinite(v) else None for v in np.asarray(values, dtype=float).tolist()]


def recorded_avoidance_radii(trajectory: Trajectory) -> FloatArray | None:
    """Each robot's avoidance radius at each frame (T, N) as a vtube log recorded it (``r_a_m``), or None: the
    trajectory is not a vtube log's, the log holds no r_a, or its rows are not the trajectory's frames."""
    path = trajectory.source.get('path')
    if trajectory.source.get('kind') != 'vtube log' or path is None:
        return None
    try:
        arrays, _ = read_log(path)
    except LogError:
        return None
    r_a, t_s = arrays.get('r_a_m'), np.asarray(arrays['t_s'], dtype=float)
    columns = [rid.removeprefix(LOG_ROBOT) for rid in trajectory.robot_ids]
    if r_a is None or r_a.ndim != 2 or not all(c.isdigit() and int(c) < r_a.shape[1] for c in columns):
        return None
    if t_s.shape != trajectory.t_s.shape or not np.allclose(t_s - t_s[0], trajectory.t_s, rtol=0.0, atol=1e-6):
        return None
    return np.asarray(r_a[:, [int(c) for c in columns]], dtype=float)


def panels(trajectory: Trajectory, scene: Scene, plan: Plan | None, frames: NDArray[np.int64]) -> list[dict[str, Any]]:
    """Density and mean speed along the tube over time at ``frames``: measured on the frames where every robot has
    a position (`along_tube`), and the plan's at the swarm centre's arc
    length while it is inside the tube (as `vtube_planning.swarm.metrics.tracking_errors` compares them)."""
    along = along_tube(trajectory, scene)
    complete = along.complete[frames]
    l_m = along.l_m[frames]
    speed = np.full(frames.size, np.nan)
    speed[complete] = along.forward_speed_mps[frames][complete].mean(axis=1)
    density = np.where(complete, along.density_per_m2[frames], np.nan)
    planned_speed, planned_density = np.full(frames.size, np.nan), np.full(frames.size, np.nan)
    if plan is not None:
        center = l_m.mean(axis=1)  # NaN where a robot has no position
        inside = complete & (center >= 0.0) & (center <= scene.tube.length_m)
        planned_speed[inside] = plan.speed(center[inside])
        planned_density[inside] = plan.density(center[inside])
    return [
        {
            'name': 'density',
            'unit': '1/m²',
            'measured': _rounded(density),
            'planned': _rounded(planned_density) if plan is not None else None,
        },
        {
            'name': 'mean speed along the tube',
            'unit': 'm/s',
            'measured': _rounded(speed),
            'planned': _rounded(planned_speed) if plan is not None else None,
        },
    ]


def _geometry(scene: Scene, positions_m: FloatArray, reach_m: float) -> dict[str, Any]:
    """The tube's centre line and walls, the obstacles' outlines (in mm) and the box that holds them and every
    robot's reach (in m)."""
    tube = scene.tube
    l_m = np.linspace(0.0, tube.length_m, TUBE_POINTS)
    center = np.asarray(tube.center_at(l_m), dtype=float)
    left, right = (np.asarray(wall, dtype=float) for wall in tube.boundaries(l_m))
    outlines = [np.asarray(o, dtype=float).T for o in scene.obstacles.outlines()] if scene.obstacles else []
    seen = positions_m.transpose(0, 2, 1).reshape(-1, 2)
    seen = seen[np.all(np.isfinite(seen), axis=1)]
    points = np.vstack([center, left, right, *outlines, seen - reach_m, seen + reach_m])
    low, high = points.min(axis=0), points.max(axis=0)
    return {
        'tube': {'center': millimetres(center), 'left': millimetres(left), 'right': millimetres(right)},
        'obstacles': [millimetres(o) for o in outlines],
        'bounds': [round(float(v), 3) for v in (*low, *high)],
    }


def replay_data(trajectory: Trajectory, scene: Scene, plan: Plan | None, plan_label: str) -> dict[str, Any]:
    """Everything the page shows, as JSON-ready values (module docstring)."""
    frames = playback_frames(trajectory.t_s)
    positions = trajectory.positions_m[frames]
    recorded = recorded_avoidance_radii(trajectory)
    r_a = recorded[frames] if recorded is not None else None
    reach = float(np.nanmax(r_a)) if r_a is not None and np.isfinite(r_a).any() else scene.swarm.r_a_m
    source = trajectory.source
    duration = float(trajectory.t_s[-1])
    shown = "each robot's recorded r_a" if r_a is not None else f"the scene's r_a = {scene.swarm.r_a_m:g} m"
    return {
        'title': f'{scene.title} ({scene.name}): {source.get("kind", "run")} {source.get("path", "")}',
        'meta': (
            f'{trajectory.n_robots} robots, {duration:.2f} s, {frames.size} of {trajectory.t_s.size} frames shown '
            f'(at most {MAX_FPS} per second of the run); tube {scene.tube.length_m:.2f} m long'
        ),
        'legend': (
            f'Discs: the robots, radius r_p = {scene.swarm.r_p_m:g} m, to scale; dashed circles: the avoidance '
            f"radius ({shown}); trails: the last {TRAIL_S:g} s; dashed line: the tube's centre line."
        ),
        'note': (
            'Panels: blue, measured on the frames where every robot has a position; '
            + (
                f"dashed, {plan_label}, at the swarm centre's arc length while it is in the tube"
                if plan
                else 'no plan is shown: the run flew none'
            )
            + '. Click a panel to seek; the space bar plays and pauses.'
        ),
        'robots': list(trajectory.robot_ids),
        'r_p_m': scene.swarm.r_p_m,
        'r_a_m': scene.swarm.r_a_m,
        'r_a': millimetres(r_a) if r_a is not None else None,
        't': [round(float(t), 3) for t in trajectory.t_s[frames]],
        'xy': millimetres(positions.transpose(0, 2, 1).reshape(frames.size, -1)),
        'trail_s': TRAIL_S,
        'panels': panels(trajectory, scene, plan, frames),
        **_geometry(scene, positions, reach),
    }


def embed(data: Any) -> str:
    """``data`` as JSON that is safe inside a ``<script>`` element: no ``<``, ``>`` or ``&`` (each a JSON escape,
    so that no string can close the element or open a comment), strict (no NaN)."""
    text = json.dumps(data, separators=(',', ':'), allow_nan=False, ensure_ascii=False)
    return text.replace('<', '\\u003c').replace('>', '\\u003e').replace('&', '\\u0026')


def replay_html(data: dict[str, Any]) -> str:
    """The page: the template with its title (HTML-escaped) and its data (`embed`) put in; each mark is
    replaced in its own part of the template, so nothing inserted is searched for a mark again."""
    template = resources.files('robotarium_exp.analysis').joinpath(TEMPLATE).read_text(encoding='utf-8')
    head, tail = template.split(DATA_MARK)
    return head.replace(TITLE_MARK, html.escape(str(data['title']))) + embed(data) + tail


def write_replay(
    trajectory: Trajectory, scene: Scene, plan: Plan | None, out: Path, plan_label: str = 'the plan'
) -> Replay:
    """Write the replay of ``trajectory`` in ``scene`` (with ``plan``'s speed and density, when given) to ``out``."""
    check_page(out)
    data = replay_data(trajectory, scene, plan, plan_label)
    write_atomically(out, replay_html(data))
    run = trajectory.t_s
    return Replay(out, out.stat().st_size, len(data['t']), int(run.size), trajectory.n_robots, float(run[-1]))
