"""The Robotarium obstacle layouts in ``docs/maps``: each generates a tube that misses its obstacles and fits the
testbed (their flights, built and checked: docs/howto/tubes.md, "Tubes from obstacle maps")."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from robotarium_exp.experiment import ExperimentConfig, flight_data
from robotarium_exp.fit import robotarium_fit
from robotarium_exp.flight_data import FlightData
from robotarium_exp.scene import load_scene
from tests.support.tube_clearance import closest_approach
from vtube_planning.geometry.from_maps.map_file import generated_scene

MAPS = Path(__file__).parents[3] / 'docs' / 'maps'


@pytest.mark.parametrize('layout', ['robotarium_discs', 'robotarium_gate', 'robotarium_staggered'])
def test_a_layout_generates_a_tube_that_misses_its_obstacles_and_fits(layout: str, tmp_path: Path) -> None:
    path = MAPS / f'{layout}.toml'
    text, made = generated_scene(path.read_text(encoding='utf-8'), str(path))
    scene_file = tmp_path / f'{layout}.toml'
    scene_file.write_text(text, encoding='utf-8')
    scene = load_scene(scene_file)
    assert scene.testbed == 'robotarium' and scene.swarm.n_robots == 6 and scene.obstacles
    fit = robotarium_fit(scene)
    assert fit.fits, fit.reason
    assert closest_approach(made.tube, scene.obstacles, 0.01, 51) >= 0.05 - 1e-9  # margin_m of the layouts
    data = FlightData.from_plain(flight_data(scene, None, ExperimentConfig(planning=False)).to_plain())
    outlines = data.obstacle_outlines_m  # what the submission draws on the testbed's figure, as it carries them
    assert len(outlines) == len(scene.obstacles.discs) + len(scene.obstacles.polygons)
    assert all(np.abs(scene.obstacles.clearance(o.T)).max() < 1e-5 for o in outlines)  # on the boundaries, rounded
