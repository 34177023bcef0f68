"""The documentation's example map (``docs/maps/forest.toml``, the README's) made into a scene end to end: its tube is
certified and misses every obstacle by the margin (checked independently, :mod:`tests.support.tube_clearance`)."""

from __future__ import annotations

from pathlib import Path

from tests.unit.vtube_planning.geometry.from_maps.test_generate import assert_misses
from vtube_planning.geometry.from_maps.map_file import generated_scene
from vtube_planning.geometry.scene import scene_from_text

ROOT = Path(__file__).resolve().parents[2]


def test_the_readme_example_map_gives_a_certified_tube_that_misses_its_obstacles() -> None:
    path = ROOT / 'docs' / 'maps' / 'forest.toml'
    text, made = generated_scene(path.read_text(encoding='utf-8'), str(path))
    scene = scene_from_text(text, name='forest', source='forest_scene.toml')
    assert len(scene.obstacles.discs) == 30 and len(scene.obstacles.polygons) == 3
    assert scene.tube.summary()['curvature_radius_min_m'] >= 4.0  # v_min^2 / a_n of Table 1
    assert_misses(made.tube, scene.obstacles, 0.3)
