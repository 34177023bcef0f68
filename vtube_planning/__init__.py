"""Speed and density planning for a speed-constrained robot swarm through a virtual tube.

Implements Song, Gao, Quan, *Speed and Density Planning for a Speed-Constrained Robot Swarm Through a Virtual
Tube* (arXiv:2310.00623). This package knows nothing of the Robotarium: scene ->
[`load_scene`][vtube_planning.geometry.scene.load_scene], plan ->
[`plan_convex`][vtube_planning.planning.planner.plan_convex] (a [`Plan`][vtube_planning.planning.plan.Plan]), fly ->
[`simulate`][vtube_planning.swarm.simulate.simulate] (a [`SimResult`][vtube_planning.swarm.simulate.SimResult]). Every
name below is imported from its module on first use.
"""

from __future__ import annotations

from importlib.metadata import version as _version
from typing import TYPE_CHECKING

from vtube_planning._lazy import lazy_exports

if TYPE_CHECKING:
    from vtube_planning.errors import (
        LogError,
        ParamsError,
        PlanError,
        SceneError,
        ShapeError,
        SolverError,
        TubeError,
        VtubeError,
    )
    from vtube_planning.geometry.centerline import ArcPath, ArcPiece, CenterCurve, SplineCurve
    from vtube_planning.geometry.scene import Scene, list_scenes, load_scene
    from vtube_planning.geometry.tube import VirtualTube
    from vtube_planning.geometry.width import WidthPart, WidthProfile
    from vtube_planning.geometry.workspace import Workspace
    from vtube_planning.log import LogWriter, read_log
    from vtube_planning.onboard import Projection, SwarmStep
    from vtube_planning.params import ControlParams, PlanningOptions, SwarmParams
    from vtube_planning.planning.plan import Plan
    from vtube_planning.planning.planner import plan_convex, replan
    from vtube_planning.swarm.metrics import PassageMetrics
    from vtube_planning.swarm.simulate import SimConfig, SimResult, simulate

__version__ = _version('vtube')
"""The installed package's version: one source of truth, the package metadata."""

__all__ = [
    'ArcPath',
    'ArcPiece',
    'CenterCurve',
    'ControlParams',
    'LogError',
    'LogWriter',
    'ParamsError',
    'PassageMetrics',
    'Plan',
    'PlanError',
    'PlanningOptions',
    'Projection',
    'Scene',
    'SceneError',
    'ShapeError',
    'SimConfig',
    'SimResult',
    'SolverError',
    'SplineCurve',
    'SwarmParams',
    'SwarmStep',
    'TubeError',
    'VirtualTube',
    'VtubeError',
    'WidthPart',
    'WidthProfile',
    'Workspace',
    '__version__',
    'list_scenes',
    'load_scene',
    'plan_convex',
    'read_log',
    'replan',
    'simulate',
]

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        'vtube_planning.errors': (
            'LogError',
            'ParamsError',
            'PlanError',
            'SceneError',
            'ShapeError',
            'SolverError',
            'TubeError',
            'VtubeError',
        ),
        'vtube_planning.geometry.centerline': ('ArcPath', 'ArcPiece', 'CenterCurve', 'SplineCurve'),
        'vtube_planning.geometry.scene': ('Scene', 'list_scenes', 'load_scene'),
        'vtube_planning.geometry.workspace': ('Workspace',),
        'vtube_planning.geometry.tube': ('VirtualTube',),
        'vtube_planning.geometry.width': ('WidthPart', 'WidthProfile'),
        'vtube_planning.log': ('LogWriter', 'read_log'),
        'vtube_planning.onboard': ('Projection', 'SwarmStep'),
        'vtube_planning.params': ('ControlParams', 'PlanningOptions', 'SwarmParams'),
        'vtube_planning.planning.plan': ('Plan',),
        'vtube_planning.planning.planner': ('plan_convex', 'replan'),
        'vtube_planning.swarm.metrics': ('PassageMetrics',),
        'vtube_planning.swarm.simulate': ('SimConfig', 'SimResult', 'simulate'),
    },
)
