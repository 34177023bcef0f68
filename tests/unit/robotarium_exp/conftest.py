"""Fixtures of the Robotarium unit tests: exact QPs, the trapezoid scene planned once, a synthetic run's arrays."""

from __future__ import annotations

import sys
from collections.abc import Iterator

import cvxopt
import numpy as np
import pytest

from robotarium_exp.rps.utilities import barrier_certificates
from robotarium_exp.rps.utilities.barrier_certificates import qp_solver, use_qp_solver
from robotarium_exp.scene import load_scene
from vtube_planning.geometry.scene import Scene
from vtube_planning.planning.plan import Plan
from vtube_planning.planning.planner import plan_convex


@pytest.fixture
def exact_qp() -> Iterator[None]:
    """The certificates solve their QPs exactly (DAQP) during the test, instead of as the testbed does."""
    previous = barrier_certificates.use_qp_solver('exact')
    yield
    barrier_certificates.use_qp_solver(previous)


@pytest.fixture(scope='session')
def trapezoid() -> tuple[Scene, Plan]:
    """The trapezoid Robotarium scene and its plan, planned once for the session."""
    scene = load_scene('robotarium_trapezoid')
    return scene, plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)


MARCH_STEPS, MARCH_DT = 300, 0.1
EXPANDS_AT = 60
"""The synthetic run's mean r_a rises by 0.03 m at this step."""


@pytest.fixture
def marching(trapezoid) -> dict[str, np.ndarray]:
    """Logged arrays of a synthetic run on the trapezoid: the swarm's centre walks the tube from -0.1 m to L + 0.1 m,
    robots 0.05 m apart along it, forward speed exactly the plan's, density 10 % above the plan's, every robot flying,
    the band held, a barrier correction of 0.01 m/s (0.05 m/s at step 7)."""
    scene, plan = trapezoid
    n, length = scene.swarm.n_robots, scene.tube.length_m
    center = np.linspace(-0.1, length + 0.1, MARCH_STEPS)
    l_m = center[:, None] + 0.05 * (np.arange(n) - (n - 1) / 2)[None, :]
    dxu = np.zeros((MARCH_STEPS, 2, n))
    dxu[:, 0, :] = plan.speed(center)[:, None]
    r_a = np.full((MARCH_STEPS, n), 0.1)
    r_a[EXPANDS_AT:] += 0.03
    correction = np.full((MARCH_STEPS, n), 0.01)
    correction[7, 2] = 0.05
    xy = scene.tube.center_at(np.clip(l_m, 0.0, length).ravel())
    positions = np.asarray(xy).reshape(MARCH_STEPS, n, 2).transpose(0, 2, 1)
    return {
        't_s': np.arange(MARCH_STEPS) * MARCH_DT,
        'l_m': l_m,
        'positions_m': positions,
        'dxu': dxu,
        'r_a_m': r_a,
        'density_per_m2': 1.1 * plan.density(center),
        'flying': np.ones((MARCH_STEPS, n), dtype=bool),
        'band_held': np.ones(MARCH_STEPS, dtype=bool),
        'barrier_correction_mps': correction,
    }


@pytest.fixture
def clean_rps(monkeypatch):
    """Whatever the test registers as ``rps...`` (and the QP solver it picks) is undone after it, and so are the
    finder ``install`` puts on ``sys.meta_path`` and what running a script changes (``sys.path``, ``__main__``,
    cvxopt's options)."""
    monkeypatch.setattr(sys, 'meta_path', list(sys.meta_path))
    monkeypatch.setattr(sys, 'path', list(sys.path))
    monkeypatch.setitem(sys.modules, '__main__', sys.modules['__main__'])
    for name in [n for n in sys.modules if n == 'rps' or n.startswith('rps.')]:
        monkeypatch.delitem(sys.modules, name)
    before, solver, options = set(sys.modules), qp_solver(), dict(cvxopt.solvers.options)
    yield
    cvxopt.solvers.options.clear()  # the dict cvxopt's solvers read: its contents restored, not another dict
    cvxopt.solvers.options.update(options)
    for name in set(sys.modules) - before:
        if name == 'rps' or name.startswith('rps.'):
            del sys.modules[name]
    use_qp_solver(solver)
