"""A log that names another tube is refused, with the fix."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.analysis.recorded_tube import check_recorded_tube
from robotarium_exp.analysis.trajectory import Trajectory
from robotarium_exp.errors import AnalysisError


def trajectory(source: dict) -> Trajectory:
    return Trajectory(np.arange(3) * 0.1, np.zeros((3, 2, 1)), None, ('r0',), source=source)


def test_the_same_tube_or_none_named_passes(trapezoid) -> None:
    scene, _ = trapezoid
    check_recorded_tube(trajectory({}), scene)
    check_recorded_tube(trajectory({'tube_hash': scene.tube.fingerprint(), 'scene': 'anything'}), scene)


def test_another_tube_is_refused_naming_the_scene_to_use(trapezoid) -> None:
    scene, _ = trapezoid
    with pytest.raises(AnalysisError, match="scene 'robotarium_curve', whose tube is not the tube of scene "
                                            "'robotarium_trapezoid'; analyse it with --scene robotarium_curve"):  # fmt: skip
        check_recorded_tube(trajectory({'tube_hash': 'other', 'scene': 'robotarium_curve'}), scene)
    with pytest.raises(AnalysisError, match='in a tube that is not .* with the scene it was recorded in'):
        check_recorded_tube(trajectory({'tube_hash': 'other'}), scene)
