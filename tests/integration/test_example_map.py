"""The documentation's example map (``docs/maps/forest.toml``, the README's) made into a scene end to end: its tube is
certified and misses every obstacle by the margin (checked independently, :mod:`tests.support.tube_clearance`); the
example maps, generated and flown, keep every body on free space inside the map over the whole run."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.unit.vtube_planning.geometry.from_maps.test_generate import assert_misses
from vtube.cli.app import main
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


@pytest.mark.parametrize('name', ['forest', 'warehouse'])
def test_the_example_maps_fly_clean_over_the_whole_run(name: str, tmp_path: Path, capsys) -> None:
    """Issue 49, item 7: a body on an obstacle or off the map at any time of the run fails it, beyond the exit too
    (the paper's model drives each robot on until the last one is through). The shipped maps give their robots room
    beyond the goal (the forest's clearing, the warehouse's yard): generated and flown, they pass."""
    scene = tmp_path / f'{name}_scene.toml'
    assert main(['tube', 'generate', str(ROOT / 'docs' / 'maps' / f'{name}.toml'), '--out', str(scene)]) == 0
    capsys.readouterr()
    assert main(['simulate', str(scene), '--out', str(tmp_path / 'sim')]) == 0
    row = next(line for line in capsys.readouterr().out.splitlines() if line.startswith('  map '))
    assert row.endswith(
        'beyond the exit, where this model drives on until the last robot is through (no parking): '
        'on obstacles 0, outside the workspace 0'
    )
