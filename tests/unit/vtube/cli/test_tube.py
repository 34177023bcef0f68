"""``vtube tube generate``: a map file in, a scene file out that every command takes; refusals exit 2.
``vtube tube example``: the shipped Robotarium maps, written where the user is."""

from __future__ import annotations

from pathlib import Path

from tests.unit.vtube_planning.geometry.test_generate import MAP_FILE
from vtube.cli.app import main
from vtube.cli.tube import COMMANDS, map_examples

COMMAND = COMMANDS[0]
ROOT = Path(__file__).resolve().parents[4]


def test_generate_writes_a_scene_that_scene_show_takes(tmp_path: Path, capsys) -> None:
    map_path, out = tmp_path / 'gap.toml', tmp_path / 'scene' / 'gap_scene.toml'
    map_path.write_text(MAP_FILE, encoding='utf-8')
    assert main([*COMMAND.words.split(), str(map_path), '--out', str(out)]) == 0
    printed = capsys.readouterr().out
    assert printed.startswith(f'tube generated from {map_path} in ') and f'written to {out}' in printed
    assert 'obstacles             clear: closest at l = ' in printed
    assert main(['scene', 'show', str(out)]) == 0
    assert 'scene gap_scene: Gap' in capsys.readouterr().out
    assert main([*COMMAND.words.split(), str(map_path), '--out', str(out)]) == 2  # never overwrites
    assert 'exists; give another file name' in capsys.readouterr().err


def test_a_map_without_a_passage_exits_2_with_the_reason(tmp_path: Path, capsys) -> None:
    map_path, out = tmp_path / 'closed.toml', tmp_path / 'closed_scene.toml'
    map_path.write_text(MAP_FILE.replace('[11.0, 4.0], [9.0, 4.0]', '[11.0, 6.9], [9.0, 6.9]'), encoding='utf-8')
    assert main([*COMMAND.words.split(), str(map_path), '--out', str(out)]) == 2
    assert 'no passage from the start to the goal' in capsys.readouterr().err
    assert not out.exists()


def test_an_image_map_generates_a_scene_elsewhere_that_still_finds_the_image(tmp_path: Path, capsys) -> None:
    """The map's image is read relative to the map file; the scene written into another folder names it relative
    to that folder, loads to the same obstacles and a tube the independent check finds clear of the margin."""
    import numpy as np
    from matplotlib.image import imsave

    from tests.support.tube_clearance import closest_approach
    from tests.unit.vtube_planning.geometry.test_occupancy import WALL, wall_image
    from vtube_planning.geometry.obstacles import Obstacles
    from vtube_planning.geometry.scene import load_scene

    maps, out = tmp_path / 'maps', tmp_path / 'out' / 'scenes' / 'gap_scene.toml'
    maps.mkdir()
    imsave(maps / 'gap.png', np.repeat(1.0 - wall_image()[:, :, None], 3, axis=2))  # occupied: black
    image = '[obstacles]\nimages = [{ file = "gap.png", resolution_m = 0.25, origin_m = [0.0, 0.0] }]\n'
    (maps / 'gap.toml').write_text(MAP_FILE.split('[obstacles]')[0] + image, encoding='utf-8')
    assert main([*COMMAND.words.split(), str(maps / 'gap.toml'), '--out', str(out)]) == 0
    assert 'file = "../../maps/gap.png"' in out.read_text(encoding='utf-8')
    scene = load_scene(out)
    assert scene.obstacles == load_scene(out).obstacles and len(scene.obstacles.images) == 1
    assert scene.obstacles.images[0].source == str(maps / 'gap.png')
    assert closest_approach(scene.tube, Obstacles(polygons=WALL), step_m=0.02, across=41) >= 0.1 - 1e-9
    capsys.readouterr()
    assert main(['scene', 'show', str(out)]) == 0


def test_the_shipped_maps_are_the_repository_layouts() -> None:
    """The package's copies of docs/maps/robotarium_*.toml (checked to fit the testbed by test_obstacle_layouts)."""
    shipped = map_examples()
    assert set(shipped) == {'robotarium_discs', 'robotarium_gate', 'robotarium_staggered'}
    for name, text in shipped.items():
        assert text == (ROOT / 'docs' / 'maps' / f'{name}.toml').read_text(encoding='utf-8'), name


def test_example_writes_a_map_that_generates_a_tube(tmp_path: Path, capsys) -> None:
    map_path, scene_path = tmp_path / 'gate.toml', tmp_path / 'gate_scene.toml'
    assert main(['tube', 'example', 'robotarium_gate', str(map_path)]) == 0
    assert f'map robotarium_gate written to {map_path}' in capsys.readouterr().out
    assert map_path.read_text(encoding='utf-8') == map_examples()['robotarium_gate']
    assert main(['tube', 'example', 'robotarium_gate', str(map_path)]) == 2  # never overwrites
    assert 'exists; give another file name' in capsys.readouterr().err
    assert main(['tube', 'generate', str(map_path), '--out', str(scene_path)]) == 0
    assert 'obstacles             clear' in capsys.readouterr().out
