"""Build the single file submitted to the remote Robotarium from a scene (``vtube submission build``).

The testbed runs one uploaded file with numpy, scipy, matplotlib, cvxopt and its own ``rps`` (no cvxpy, no package
of ours), so the file carries everything: the plan computed here as arrays, the tube as samples, the initial
conditions and parking slots, the sources of the package functions the runtime needs, and the runtime itself
(:mod:`submission.runtime`). The output is deterministic (no time stamps, no paths, numbers rounded to six
significant digits), so a committed submission can be checked against a fresh build.
"""

from __future__ import annotations

import importlib
import inspect
import pprint
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from robotarium_exp.experiment import ARENA, ExperimentConfig, initial_conditions, parking_slots
from submission import runtime
from vtube_planning.errors import VtubeError
from vtube_planning.planning.planner import plan_convex
from vtube_planning.geometry.scene import Scene, load_scene

MAX_ROBOTS = 20
"""Robots on the hardware testbed."""
ARENA_MARGIN_M = 0.05
RUNTIME_MARKER = '# ---- runtime ----'
PACKAGE_VERSION = '0.1.0'


class SubmissionError(VtubeError, ValueError):
    """A scene that cannot become a valid submission."""


@dataclass(frozen=True)
class Submission:
    """The generated source and what it was built from."""

    source: str
    scene: str
    planned: bool
    n_robots: int


def build(name_or_path: str | Path, *, planning: bool = True) -> Submission:
    """The submission's source for a Robotarium scene (shipped name or .toml file)."""
    scene = load_scene(name_or_path)
    _check_scene(scene)
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    config = ExperimentConfig(planning=planning)
    tube = scene.tube
    samples = np.linspace(0.0, tube.length_m, max(2, int(np.ceil(tube.length_m / 0.01)) + 1))
    coarse = np.linspace(0.0, tube.length_m, 120)
    left, right = tube.boundaries(coarse)
    ic, slots = initial_conditions(scene), parking_slots(scene)
    for name, points in (('initial conditions', ic[:2]), ('parking slots', slots)):
        _inside_arena(scene, name, points.T)
    data = {
        'scene': scene.name,
        'planned': planning,
        'swarm': asdict(scene.swarm),
        'control': {**asdict(scene.control), 'r_a_max_m': scene.control.radius_cap(scene.swarm)},
        'projection_distance_m': config.projection_distance_m,
        'barrier': {'safety_radius_m': config.safety_radius_m},
        'max_steps': config.max_steps,
        'initial_conditions': ic,
        'parking_slots': slots,
        'tube': {'l': samples, 'xy': tube.center_at(samples).T, 'half_width': tube.half_width(samples),
                 'area': tube.area(samples), 'edges': np.stack([left.T, right.T])},
        'plan': {'l': plan.l_m, 'speed': plan.speed_mps, 'density': plan.density_per_m2},
    }
    header = _header(scene, plan, planning)
    source = '\n'.join([
        header,
        'from __future__ import annotations',
        '',
        'import math',
        '',
        'import numpy as np',
        '',
        f'DATA = {pprint.pformat(_plain(data), width=118, compact=True, sort_dicts=False)}',
        '',
        '# ---- from the vtube package (inlined so that the testbed needs nothing of ours) ----',
        _inlined_sources(),
        _runtime_body(),
        '',
        "if __name__ == '__main__':",
        '    import rps.robotarium as robotarium',
        '',
        '    run(DATA, robotarium)',
        '',
    ])
    return Submission(source=source, scene=scene.name, planned=planning, n_robots=scene.swarm.n_robots)


def write(submission: Submission, path: str | Path) -> Path:
    """Write the submission's source; creates the folder."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(submission.source, encoding='utf-8')
    return path


def _check_scene(scene: Scene) -> None:
    n = scene.swarm.n_robots
    if n > MAX_ROBOTS:
        msg = f'scene {scene.name!r} has {n} robots; the Robotarium runs at most {MAX_ROBOTS}. Lower n_robots.'
        raise SubmissionError(msg)
    grid = np.linspace(0.0, scene.tube.length_m, 400)
    for side in scene.tube.boundaries(grid):
        _inside_arena(scene, 'tube boundary', side)


def _inside_arena(scene: Scene, what: str, points: np.ndarray) -> None:
    xmin, xmax, ymin, ymax = ARENA
    m = ARENA_MARGIN_M
    outside = (points[:, 0] < xmin + m) | (points[:, 0] > xmax - m) | (points[:, 1] < ymin + m) | (points[:, 1] > ymax - m)
    if outside.any():
        k = int(np.argmax(outside))
        msg = (f'scene {scene.name!r} does not fit the Robotarium arena: its {what} reaches '
               f'({points[k, 0]:.3f}, {points[k, 1]:.3f}), outside [-1.6, 1.6] x [-1, 1] less {m} m; move or shorten '
               'the tube (a Robotarium scene needs a [workspace] with the arena).')
        raise SubmissionError(msg)


def _plain(value: Any) -> Any:
    """Arrays as nested lists of floats rounded to six significant digits; dicts and scalars as they are."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, float):
        return float(f'{value:.6g}')
    return value


def _header(scene: Scene, plan: Any, planning: bool) -> str:
    certified = 'every constraint holds within 1e-6 (relative)' if plan.is_certified() else (
        f'NOT certified, largest relative violation {max(plan.certificate.values()):.1e}')
    return '\n'.join([
        '"""vtube: a speed- and density-planned robot swarm through a virtual tube, for the Robotarium.',
        '',
        f'Scene {scene.name!r}: {scene.title}. {scene.swarm.n_robots} robots, '
        f'{"with" if planning else "without"} speed and density planning.',
        '',
        'Declare on the web form: the robot count above, and the duration that `vtube submission check` reports.',
        f'Plan: convex slowness method, {plan.l_m.size} grid points, traversal time {plan.time_s:.2f} s; certificate:',
        f'{certified}. Arrays rounded to six significant digits.',
        'Method: Song, Gao, Quan, "Speed and Density Planning for a Speed-Constrained Robot Swarm Through a Virtual',
        'Tube" (arXiv:2310.00623), as implemented by the vtube package.',
        '',
        f'Generated by vtube {PACKAGE_VERSION}; do not edit. Rebuild with:',
        f'    vtube submission build {scene.name} --out FILE{"" if planning else " --no-planning"}',
        'It imports only the standard library, numpy and the testbed\'s rps. It saves vtube_*.npy every 100 steps',
        'and at the end, and prints one JSON summary line to stdout (log.txt).',
        '"""',
        '',
    ])


def _inlined_sources() -> str:
    parts = []
    for module_name, names in runtime.INLINED:
        module = importlib.import_module(module_name)
        for name in names:
            value = getattr(module, name)
            if isinstance(value, (int, float)):
                parts.append(f'{name} = {value!r}')
            else:
                parts.append(inspect.getsource(value).rstrip())
                for helper in _private_helpers(value, module):
                    parts.insert(-1, inspect.getsource(helper).rstrip())
    return '\n\n\n'.join(dict.fromkeys(parts)) + '\n\n'


def _private_helpers(func: Any, module: Any) -> list[Any]:
    """Module-private functions (``_name``) a function calls, which must travel with it."""
    code = getattr(func, '__code__', None)
    if code is None:
        return []
    return [getattr(module, n) for n in code.co_names if n.startswith('_') and inspect.isfunction(getattr(module, n, None))]


def _runtime_body() -> str:
    text = inspect.getsource(runtime)
    return text[text.index(RUNTIME_MARKER) + len(RUNTIME_MARKER):].strip() + '\n'
