"""Speed and density planning for a speed-constrained robot swarm through a virtual tube.

Implements Song, Gao, Quan, *Speed and Density Planning for a Speed-Constrained Robot Swarm Through a Virtual
Tube* (arXiv:2310.00623). This package knows nothing of the Robotarium: it holds the tube geometry, the scenes,
the swarm parameters and (in later modules) the planner, the controller and the simulator.
"""

from importlib.metadata import version as _version

from vtube_planning.errors import ParamsError, PlanError, SceneError, ShapeError, SolverError, TubeError, VtubeError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece, CenterCurve, SplineCurve
from vtube_planning.geometry.scene import Scene, Workspace, list_scenes, load_scene
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.onboard import Projection
from vtube_planning.params import PlanningOptions, SwarmParams

__version__ = _version('vtube')
"""The installed package's version: one source of truth, the package metadata."""

__all__ = [
    'ArcPath',
    'ArcPiece',
    'CenterCurve',
    'ParamsError',
    'PlanError',
    'PlanningOptions',
    'Projection',
    'Scene',
    'SceneError',
    'ShapeError',
    'SolverError',
    'SplineCurve',
    'SwarmParams',
    'TubeError',
    'VirtualTube',
    'VtubeError',
    'WidthPart',
    'WidthProfile',
    'Workspace',
    '__version__',
    'list_scenes',
    'load_scene',
]
