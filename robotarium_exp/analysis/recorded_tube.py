"""Whether a recording was made in a scene's tube: a log that names its tube is measured only in that tube."""

from __future__ import annotations

from robotarium_exp.analysis.trajectory import Trajectory
from robotarium_exp.errors import AnalysisError
from vtube_planning.geometry.scene import Scene


def check_recorded_tube(trajectory: Trajectory, scene: Scene) -> None:
    """Refuse ``trajectory`` when its log records the fingerprint of another tube than ``scene``'s."""
    recorded = trajectory.source.get('tube_hash')
    if recorded is None or recorded == scene.tube.fingerprint():
        return
    name = trajectory.source.get('scene')
    where = f'scene {name!r}, whose tube' if name else 'a tube that'
    fix = f'--scene {name}' if name else 'the scene it was recorded in'
    msg = (
        f'the log was recorded in {where} is not the tube of scene {scene.name!r}; analyse it with {fix}, or leave '
        '--scene out for the tube-free metrics.'
    )
    raise AnalysisError(msg)
