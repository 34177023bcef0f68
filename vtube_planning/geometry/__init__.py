"""The virtual tube and its scenes: centre curve, half-width profile, projection, scene files."""

from __future__ import annotations

from typing import TYPE_CHECKING

from vtube_planning._lazy import lazy_exports

if TYPE_CHECKING:
    from vtube_planning.geometry.centerline import ArcPath, ArcPiece, CenterCurve, SplineCurve
    from vtube_planning.geometry.scene import Scene, list_scenes, load_scene
    from vtube_planning.geometry.tube import VirtualTube
    from vtube_planning.geometry.width import WidthPart, WidthProfile
    from vtube_planning.geometry.workspace import Workspace
    from vtube_planning.onboard import Projection, SampledTube

__all__ = [
    'ArcPath',
    'ArcPiece',
    'CenterCurve',
    'Projection',
    'SampledTube',
    'Scene',
    'SplineCurve',
    'VirtualTube',
    'WidthPart',
    'WidthProfile',
    'Workspace',
    'list_scenes',
    'load_scene',
]

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        'vtube_planning.geometry.centerline': ('ArcPath', 'ArcPiece', 'CenterCurve', 'SplineCurve'),
        'vtube_planning.onboard': ('Projection', 'SampledTube'),
        'vtube_planning.geometry.scene': ('Scene', 'list_scenes', 'load_scene'),
        'vtube_planning.geometry.workspace': ('Workspace',),
        'vtube_planning.geometry.tube': ('VirtualTube',),
        'vtube_planning.geometry.width': ('WidthPart', 'WidthProfile'),
    },
)
