"""``vtube tube generate``: a map file in, a scene file out that every command takes; refusals exit 2.
``vtube tube example``: the shipped Robotarium maps, written where the user is."""

from __future__ import annotations

from pathlib import Path

from tests.unit.vtube_planning.geometry.from_maps.test_generate import MAP_FILE
from vtube.cli.app import main
from vtube.cli.tube import COMMANDS, map_examples

COMMAND = COMMANDS[0]
ROOMY = (
    MAP_FILE.replace('start_m = [1.0, 2.0]', 'start_m = [3.0, 3.0]')
    .replace('goal_m = [19.0, 8.0]', 'goal_m = [15.0, 6.0]')
    .replace('v_min_mps', 'n_robots = 4\nv_min_mps')
)
"""The gap map with room behind its start for the start formation of its swarm, and ahead of its goal for their
run-out (`vtube tube generate` checks both)."""
SWARM = ROOMY[ROOMY.index('[swarm]') :]
ROOT = Path(__file__).resolve().parents[4]


def test_generate_writes_a_scene_that_scene_show_takes(tmp_path: Path, capsys) -> None:
    map_path, out = tmp_path / 'gap.toml', tmp_path / 'scene' / 'gap_scene.toml'
    map_path.write_text(ROOMY, encoding='utf-8')
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
    (maps / 'gap.toml').write_text(ROOMY.split('[obstacles]')[0] + image + SWARM, encoding='utf-8')
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


def test_a_straight_route_across_unknown_cells_goes_around_them_unless_they_are_freed(tmp_path: Path, capsys) -> None:
    """Issue 49: a map whose straight route crosses cells never mapped (map_server's grey 205). By default they are
    obstacles: the tube goes around and touches none. With ``unknown = "free"`` it may cross them, and the output,
    the scene file and its figure say so."""
    import numpy as np
    from matplotlib.image import imsave

    from vtube_planning.geometry.scene import load_scene

    pixels = np.full((40, 80), 254, dtype=np.uint8)  # 20 x 10 m at 0.25 m: free
    pixels[:28, 36:44] = 205  # x in [9, 11], y in [3, 10]: never mapped, across the straight route y = 5
    imsave(tmp_path / 'unmapped.png', pixels, cmap='gray', vmin=0, vmax=255)
    route = ROOMY.split('[obstacles]')[0].replace('start_m = [3.0, 3.0]', 'start_m = [4.0, 5.0]')
    route = route.replace('goal_m = [15.0, 6.0]', 'goal_m = [16.0, 5.0]')
    image = '[obstacles]\nimages = [{ file = "unmapped.png", resolution_m = 0.25, origin_m = [0.0, 0.0]%s }]\n'
    (tmp_path / 'map.toml').write_text(route + image % '' + SWARM, encoding='utf-8')
    (tmp_path / 'free.toml').write_text(route + image % ', unknown = "free"' + SWARM, encoding='utf-8')

    def tube_on_unknown(scene_file: Path) -> float:
        scene = load_scene(scene_file)
        l_m = np.linspace(0.0, scene.tube.length_m, 2000)
        left, right = scene.tube.boundaries(l_m)
        points = np.concatenate([scene.tube.center_at(l_m), left, right])
        return float(scene.obstacles.images[0].on_unknown(points).mean())

    assert main([*COMMAND.words.split(), str(tmp_path / 'map.toml'), '--out', str(tmp_path / 'a.toml')]) == 0
    printed = capsys.readouterr().out
    assert '  unknown cells         occupied (never mapped is never free' in printed
    assert tube_on_unknown(tmp_path / 'a.toml') == 0.0  # around the unmapped block, below it
    assert 'unknown = "occupied"' in (tmp_path / 'a.toml').read_text(encoding='utf-8')
    assert main([*COMMAND.words.split(), str(tmp_path / 'free.toml'), '--out', str(tmp_path / 'b.toml')]) == 0
    printed = capsys.readouterr().out
    line = next(line for line in printed.splitlines() if line.startswith('  unknown cells'))
    share = float(line.split('FREE (unknown = "free"): ')[1].split(' %')[0])
    assert tube_on_unknown(tmp_path / 'b.toml') > 0.0 and 5.0 < share < 30.0  # 2 m of a straight 12 m tube: 17 %
    text = (tmp_path / 'b.toml').read_text(encoding='utf-8')
    assert '# unknown cells of the images count as FREE here' in text and 'unknown = "free"' in text
