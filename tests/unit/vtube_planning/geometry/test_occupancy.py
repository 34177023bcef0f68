"""Occupancy images as obstacles: the exact clearance of the occupied squares (analytic, brute force, the same
rectangles as polygons), ROS map_server's orientation and thresholds, files read and refused, the table's round
trip, the search grid's conservative rasterisation, and a tube generated on an image, checked independently."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imsave

from tests.support.tube_clearance import closest_approach
from vtube_planning.errors import SceneError
from vtube_planning.geometry import occupancy
from vtube_planning.geometry.from_maps.centre_path import SearchGrid
from vtube_planning.geometry.from_maps.generate import TubeSpec, generate_tube
from vtube_planning.geometry.obstacles import Disc, Obstacles, Polygon, obstacles_from_table
from vtube_planning.geometry.occupancy import OCCUPIED_THRESH, OccupancyImage, image_from_entry
from vtube_planning.geometry.workspace import Workspace


def squares(image: OccupancyImage) -> tuple[np.ndarray, np.ndarray]:
    """Every occupied pixel's square, lower and upper corners (n, 2), written out from the convention (row 0 the
    top, origin the lower-left corner of the bottom-left pixel)."""
    rows = image.occupied.shape[0]
    i, j = np.nonzero(image.occupied)
    x0, y0, r = image.origin_m[0], image.origin_m[1], image.resolution_m
    low = np.column_stack([x0 + j * r, y0 + (rows - 1 - i) * r])
    return low, low + r


def brute_clearance(image: OccupancyImage, points: np.ndarray) -> np.ndarray:
    """The distance of each point to every occupied square, least (inf without one)."""
    low, high = squares(image)
    if not len(low):
        return np.full(len(points), np.inf)
    gap = np.maximum(np.maximum(low[None] - points[:, None], 0.0), points[:, None] - high[None])
    return np.hypot(gap[..., 0], gap[..., 1]).min(axis=1)


def test_a_single_pixel_is_a_closed_square_of_the_resolution() -> None:
    image = OccupancyImage(np.array([[True]]), 0.5, (2.0, 3.0))  # the square [2, 2.5] x [3, 3.5]
    points = np.array([[1.0, 3.2], [3.0, 4.0], [2.25, 3.25], [2.5, 3.5], [2.2, 2.0], [1.7, 3.9], [2.5, 3.0]])
    expected = [1.0, math.hypot(0.5, 0.5), 0.0, 0.0, 1.0, math.hypot(0.3, 0.4), 0.0]
    np.testing.assert_allclose(image.clearance(points), expected, rtol=0, atol=1e-15)
    assert image.inside(points).tolist() == [False, False, True, True, False, False, True]
    assert image.extent_m == (2.0, 2.5, 3.0, 3.5)
    assert np.isinf(OccupancyImage(np.zeros((3, 4), bool), 0.1, (0.0, 0.0)).clearance(points)).all()


@pytest.mark.parametrize('first_k', [1, 16])
@pytest.mark.parametrize('seed', range(4))
def test_clearance_is_the_distance_to_the_nearest_of_all_occupied_squares(seed: int, first_k: int, monkeypatch) -> None:
    """Against every occupied square; from 1 nearest centre asked at first (doubled until the candidates are
    proved enough) and from 16."""
    monkeypatch.setattr(occupancy, '_FIRST_K', first_k)
    rng = np.random.default_rng(seed)
    shape = tuple(int(n) for n in rng.integers(1, 40, size=2))
    occupied = rng.random(shape) < rng.uniform(0.02, 0.9)
    image = OccupancyImage(occupied, float(rng.uniform(0.03, 0.7)), tuple(rng.uniform(-5.0, 5.0, size=2)))
    x_min, x_max, y_min, y_max = image.extent_m
    span = max(x_max - x_min, y_max - y_min)
    points = np.vstack(
        [
            rng.uniform([x_min - span, y_min - span], [x_max + span, y_max + span], (1500, 2)),
            rng.uniform([x_min, y_min], [x_max, y_max], (1500, 2)),
            squares(image)[0][:200] if occupied.any() else np.empty((0, 2)),  # corners: on the squares
            rng.uniform(-1e3, 1e3, (20, 2)),
        ]
    )
    expected = brute_clearance(image, points)
    got = image.clearance(points)
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-12)
    assert np.array_equal(image.inside(points), expected == 0.0)


def test_clearance_agrees_with_each_pixel_as_a_polygon() -> None:
    """An oracle that shares no code with the image's: each occupied pixel a square Polygon."""
    rng = np.random.default_rng(7)
    image = OccupancyImage(rng.random((6, 9)) < 0.3, 0.25, (-1.0, 0.5))
    low, high = squares(image)
    polygons = tuple(
        Polygon(((a[0], a[1]), (b[0], a[1]), (b[0], b[1]), (a[0], b[1]))) for a, b in zip(low, high, strict=True)
    )
    points = rng.uniform([-2.0, -0.5], [2.5, 3.0], (3000, 2))
    np.testing.assert_allclose(
        Obstacles(images=(image,)).clearance(points), Obstacles(polygons=polygons).clearance(points), atol=1e-12
    )


MAP = Workspace(0.0, 20.0, 0.0, 10.0, margin_m=0.2)
WALL = (
    Polygon(((9.0, 0.0), (11.0, 0.0), (11.0, 4.0), (9.0, 4.0))),
    Polygon(((9.0, 7.0), (11.0, 7.0), (11.0, 10.0), (9.0, 10.0))),
    Polygon(((4.0, 6.0), (5.5, 6.0), (5.5, 7.5), (4.0, 7.5))),
)


def wall_image(resolution_m: float = 0.25) -> np.ndarray:
    """The map 20 x 10 m with the rectangles of WALL occupied, row 0 the top, as a map_server image would be."""
    rows, cols = round(10.0 / resolution_m), round(20.0 / resolution_m)
    x = (np.arange(cols) + 0.5) * resolution_m
    y = 10.0 - (np.arange(rows) + 0.5) * resolution_m  # row 0 the top
    occupied = np.zeros((rows, cols), bool)
    for polygon in WALL:
        (x_lo, y_lo), (x_hi, y_hi) = np.min(polygon.vertices_m, axis=0), np.max(polygon.vertices_m, axis=0)
        occupied |= ((y[:, None] > y_lo) & (y[:, None] < y_hi)) & ((x[None] > x_lo) & (x[None] < x_hi))
    return occupied


def test_cell_aligned_rectangles_are_the_same_obstacles_as_polygons() -> None:
    image = Obstacles(images=(OccupancyImage(wall_image(), 0.25, (0.0, 0.0)),))
    polygons = Obstacles(polygons=WALL)
    rng = np.random.default_rng(3)
    points = rng.uniform([-3.0, -3.0], [23.0, 13.0], (5000, 2))
    np.testing.assert_allclose(image.clearance(points), polygons.clearance(points), rtol=0, atol=1e-12)
    assert np.array_equal(image.inside(points), polygons.inside(points))


def test_a_tube_generated_on_the_image_is_certified_and_clear_by_the_independent_check() -> None:
    obstacles = Obstacles(images=(OccupancyImage(wall_image(), 0.25, (0.0, 0.0)),))
    spec = TubeSpec(MAP, obstacles, (1.0, 2.0), (19.0, 8.0), 0.5, 2.0, margin_m=0.1, resolution_m=0.1)
    made = generate_tube(spec)
    assert made.certificate.clear
    assert made.tube.project(np.array([[10.0], [5.5]])).y_m[0] ** 2 < 1.0  # through the gap at y in [4, 7]
    # tests/support/tube_clearance.py on the same rectangles as polygons: none of the image's code
    assert closest_approach(made.tube, Obstacles(polygons=WALL), step_m=0.02, across=41) >= 0.1 - 1e-9


def test_the_search_grid_marks_a_wall_thinner_than_its_cells() -> None:
    """A wall of 5 cm pixels between two columns of 10 cm nodes: no node lies in it, yet the grid's clearance
    stays a lower bound of the exact one (every node whose cell the wall meets counts as occupied)."""
    occupied = np.zeros((200, 1), bool)
    occupied[20:180] = True  # y in [1, 9]
    wall = OccupancyImage(occupied, 0.05, (1.075, 0.0))  # x in [1.075, 1.125]: nodes at 1.05 and 1.15
    spec = TubeSpec(MAP, Obstacles(images=(wall,)), (0.5, 5.0), (19.0, 5.0), 0.3, 1.0, resolution_m=0.1)
    grid = SearchGrid(spec)
    assert not wall.inside(np.column_stack([grid.x, np.full(grid.x.size, 5.0)])).any()
    xx, yy = np.meshgrid(grid.x, grid.y, indexing='ij')
    exact = spec.obstacles.clearance(np.column_stack([xx.ravel(), yy.ravel()])).reshape(xx.shape)
    assert np.all(grid.clear <= exact + 1e-12)
    assert not grid.free[np.abs(grid.x - 1.1) < 0.1][:, np.abs(grid.y - 5.0) < 1.0].any()


@pytest.mark.parametrize('seed', range(3))
def test_meets_squares_is_the_overlap_of_closed_boxes(seed: int) -> None:
    rng = np.random.default_rng(seed)
    image = OccupancyImage(rng.random((12, 15)) < 0.15, 0.1, (0.3, -0.2))
    centres = rng.uniform([-0.2, -0.7], [2.2, 1.5], (2000, 2))
    half = float(rng.uniform(0.01, 0.2))
    low, high = squares(image)
    overlap = np.all((low[None] <= centres[:, None] + half) & (high[None] >= centres[:, None] - half), axis=2)
    assert np.array_equal(image.meets_squares(centres, half), overlap.any(axis=1))


def write_pgm(path: Path, pixels: np.ndarray) -> None:
    rows, cols = pixels.shape
    path.write_bytes(f'P5\n{cols} {rows}\n255\n'.encode() + pixels.astype(np.uint8).tobytes())


def test_a_dark_top_left_pixel_lands_at_the_top_left_of_the_map(tmp_path: Path) -> None:
    """ROS map_server: the origin is the lower-left corner, row 0 the top; a pixel is occupied where 1 - grey
    exceeds occupied_thresh (PNG, PGM and .npy alike)."""
    grey = np.ones((3, 4))
    grey[0, 0] = 0.0
    imsave(tmp_path / 'map.png', np.repeat(grey[:, :, None], 3, axis=2))
    write_pgm(tmp_path / 'map.pgm', grey * 255)
    np.save(tmp_path / 'map.npy', 1.0 - grey)
    top_left, bottom_left = np.array([[10.25, 21.25]]), np.array([[10.25, 20.25]])
    for name in ('map.png', 'map.pgm', 'map.npy'):
        entry = {'file': name, 'resolution_m': 0.5, 'origin_m': [10.0, 20.0]}
        image = image_from_entry(entry, tmp_path)
        assert image.extent_m == (10.0, 12.0, 20.0, 21.5)
        assert image.inside(top_left)[0] and not image.inside(bottom_left)[0], name
        assert image.clearance(np.array([[10.25, 22.0]]))[0] == pytest.approx(0.5)  # above the top row
        assert image.source == str(tmp_path / name) and image.occupied_thresh == OCCUPIED_THRESH


def test_grey_levels_colours_and_alpha_follow_map_server(tmp_path: Path) -> None:
    rgba = np.ones((1, 5, 4))
    rgba[0, 0, :3] = (1.0, 0.0, 0.0)  # grey 1/3: darkness 2/3 > 0.65, occupied
    rgba[0, 1, :3] = 0.36  # darkness 0.64: unknown (between free_thresh and occupied_thresh)
    rgba[0, 2, :3] = 0.30  # darkness 0.70: occupied
    rgba[0, 3] = (0.0, 0.0, 0.0, 0.0)  # black, transparent: alpha ignored, occupied
    imsave(tmp_path / 'rgba.png', rgba)
    entry = {'file': 'rgba.png', 'resolution_m': 1.0, 'origin_m': [0.0, 0.0], 'unknown': 'free'}
    assert image_from_entry(entry, tmp_path).occupied.tolist() == [[True, False, True, True, False]]
    lower = image_from_entry({**entry, 'occupied_thresh': 0.6}, tmp_path)
    assert lower.occupied.tolist() == [[True, True, True, True, False]]
    np.save(tmp_path / 'flags.npy', np.array([[True, False], [False, True]]))
    flags = image_from_entry({**entry, 'file': 'flags.npy'}, tmp_path)
    assert flags.occupied.tolist() == [[True, False], [False, True]]


@pytest.mark.parametrize(
    ('file', 'content', 'change', 'message'),
    [
        ('none.png', None, {}, r"none\.png' does not exist \(file = 'none\.png' is read relative to the scene"),
        ('text.png', b'hello', {}, r'is not an image matplotlib can read .*give a PNG or PGM'),
        ('objects.npy', 'pickle', {}, r'holds pickled data, which is refused; save a plain .* np\.save'),
        ('cube.npy', np.zeros((2, 2, 2)), {}, r'must hold a non-empty 2-D array \(rows, columns\); got \(2, 2, 2\)'),
        ('empty.npy', np.zeros((0, 3)), {}, r'must hold a non-empty 2-D array'),
        ('nan.npy', np.array([[0.5, np.nan]]), {}, r'occupancy probabilities in \[0, 1\].*divide by 100'),
        ('grid.npy', np.array([[0, 100, -1]]), {}, r'occupancy probabilities in \[0, 1\]'),
        ('ok.npy', np.zeros((2, 2)), {'resolution_m': 0.0}, r'resolution_m \(metres per pixel\) must be .* > 0'),
        ('ok.npy', np.zeros((2, 2)), {'resolution_m': 'fine'}, r'resolution_m .* must be a finite number > 0'),
        ('ok.npy', np.zeros((2, 2)), {'origin_m': [float('nan'), 0.0]}, r'origin_m must be \[x, y\], two finite'),
        ('ok.npy', np.zeros((2, 2)), {'origin_m': [1.0]}, r'origin_m must be \[x, y\]'),
        ('ok.npy', np.zeros((2, 2)), {'occupied_thresh': 1.0}, r'occupied_thresh of .* must be a number in \[0, 1\)'),
        ('ok.npy', np.zeros((2, 2)), {'file': 3}, r'file must be the path of a PNG/PGM image or a \.npy array'),
        ('ok.npy', np.zeros((2, 2)), {'negate': 0}, r"needs the keys \['file', 'origin_m', 'resolution_m'\]"),
    ],
)
def test_bad_images_are_refused_naming_the_problem_and_the_fix(tmp_path, file, content, change, message) -> None:
    if isinstance(content, bytes):
        (tmp_path / file).write_bytes(content)
    elif isinstance(content, str):
        np.save(tmp_path / file, np.array([{'a': 1}], dtype=object))  # pickled: np.save's default
    elif content is not None:
        np.save(tmp_path / file, content)
    entry = {'file': file, 'resolution_m': 0.1, 'origin_m': [0.0, 0.0], **change}
    with pytest.raises(SceneError, match=message):
        obstacles_from_table({'images': [entry]}, tmp_path)


def test_an_image_made_in_code_is_checked_too() -> None:
    with pytest.raises(SceneError, match=r'non-empty 2-D boolean array; got shape \(2, 2, 3\)'):
        OccupancyImage(np.zeros((2, 2, 3), bool), 0.1, (0.0, 0.0))
    with pytest.raises(SceneError, match='made in code has no file to write'):
        Obstacles(images=(OccupancyImage(np.ones((1, 1), bool), 0.1, (0.0, 0.0)),)).table()
    with pytest.raises(SceneError, match=r'\[obstacles\] images must be a list'):
        obstacles_from_table({'images': {'file': 'a.png'}})


def test_the_table_round_trips_relative_to_any_folder_and_the_obstacles_hash(tmp_path: Path) -> None:
    maps, scenes = tmp_path / 'maps', tmp_path / 'out' / 'scenes'
    maps.mkdir()
    np.save(maps / 'room.npy', np.eye(4))
    table = {
        'discs': [{'center_m': [1.0, 2.0], 'radius_m': 0.5}],
        'images': [{'file': 'room.npy', 'resolution_m': 0.05, 'origin_m': [-1.0, 0.5], 'occupied_thresh': 0.5}],
    }
    obstacles = obstacles_from_table(table, maps)
    assert obstacles.discs == (Disc((1.0, 2.0), 0.5),) and obstacles.images[0].occupied.sum() == 4
    assert obstacles_from_table(obstacles.table(maps), maps) == obstacles
    written = obstacles.table(scenes)
    assert written['images'][0]['file'] == '../../maps/room.npy' and written['images'][0]['occupied_thresh'] == 0.5
    assert obstacles_from_table(written, scenes) == obstacles
    assert Path(obstacles.table()['images'][0]['file']).is_absolute()
    assert hash(obstacles) == hash(obstacles_from_table(written, scenes)) and bool(obstacles)
    moved = obstacles_from_table({'images': [{**table['images'][0], 'origin_m': [-1.0, 0.55]}]}, maps)
    assert moved != Obstacles(images=obstacles.images)


def test_the_warehouse_example_generates_a_tube_clear_of_its_drawn_boxes(tmp_path: Path) -> None:
    """docs/maps/warehouse.toml: its image is the boxes warehouse.py draws (pixel-aligned), and the tube generated
    keeps its margin from them as polygons (the independent check)."""
    import importlib.util

    from vtube_planning.geometry.from_maps.map_file import generated_scene
    from vtube_planning.geometry.scene import load_scene

    maps = Path(__file__).parents[4] / 'docs' / 'maps'
    spec = importlib.util.spec_from_file_location('warehouse', maps / 'warehouse.py')
    assert spec is not None and spec.loader is not None
    drawing = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(drawing)
    boxes = Obstacles(
        polygons=tuple(Polygon(((a, c), (b, c), (b, d), (a, d))) for a, b, c, d in drawing.BOXES_M),
    )
    source = maps / 'warehouse.toml'
    text, made = generated_scene(source.read_text(encoding='utf-8'), str(source), tmp_path)  # written there
    (tmp_path / 'warehouse_scene.toml').write_text(text, encoding='utf-8')
    scene = load_scene(tmp_path / 'warehouse_scene.toml')
    (image,) = scene.obstacles.images
    assert np.array_equal(image.occupied, drawing.occupancy())
    points = np.random.default_rng(5).uniform([-1.0, -1.0], [41.0, 21.0], (4000, 2))
    np.testing.assert_allclose(scene.obstacles.clearance(points), boxes.clearance(points), rtol=0, atol=1e-12)
    assert closest_approach(made.tube, boxes, step_m=0.04, across=31) >= 0.2 - 1e-9  # margin_m of the map


def test_a_scene_file_reads_its_image_beside_it_and_refuses_a_tube_through_it(tmp_path: Path) -> None:
    from tests.unit.vtube_planning.geometry.test_obstacles import SCENE
    from vtube_planning.geometry.scene import load_scene

    block = np.ones((2, 2), bool)  # 1 x 1 m at 0.5 m per pixel; the tube: y in [-2, 2] for x in [0, 10]
    np.save(tmp_path / 'block.npy', block)
    text = SCENE.split('[obstacles]')[0] + '[obstacles]\nimages = [{ file = "block.npy", resolution_m = 0.5, '
    (tmp_path / 'clear.toml').write_text(text + 'origin_m = [4.5, 2.1] }]\n', encoding='utf-8')
    assert load_scene(tmp_path / 'clear.toml').obstacles.images[0].occupied.all()
    (tmp_path / 'through.toml').write_text(text + 'origin_m = [4.5, 1.5] }]\n', encoding='utf-8')
    with pytest.raises(SceneError, match=r'through\.toml: the tube meets an obstacle: at l = .*move or narrow'):
        load_scene(tmp_path / 'through.toml')


def test_unknown_cells_are_occupied_unless_the_entry_says_free(tmp_path: Path) -> None:
    """Issue 49: on the Willow Garage map 57 % of a certified tube lay on cells never mapped (map_server's grey
    205, darkness 0.196): unknown cells are obstacles by default; ``unknown = "free"`` frees them and is written
    back to the scene file's entry."""
    grey = np.array([[254, 205, 0, 128]], dtype=np.uint8)  # free, unknown, occupied, unknown (darkness 0.498)
    imsave(tmp_path / 'ros.png', grey, cmap='gray', vmin=0, vmax=255)
    entry = {'file': 'ros.png', 'resolution_m': 0.5, 'origin_m': [0.0, 0.0]}
    default = image_from_entry(entry, tmp_path)
    assert default.occupied.tolist() == [[False, True, True, True]]
    assert default.unknown_cells is not None and default.unknown_cells.tolist() == [[False, True, False, True]]
    assert default.entry(tmp_path)['unknown'] == 'occupied' and default.entry(tmp_path)['free_thresh'] == 0.196
    free = image_from_entry({**entry, 'unknown': 'free'}, tmp_path)
    assert free.occupied.tolist() == [[False, False, True, False]] and free.entry(tmp_path)['unknown'] == 'free'
    assert free.on_unknown(np.array([[0.75, 0.25], [0.25, 0.25], [1.75, 0.1], [9.0, 0.2]])).tolist() == [
        True,
        False,
        True,
        False,
    ]
    stricter = image_from_entry({**entry, 'free_thresh': 0.6}, tmp_path)  # 0.498 is now free, 205 too
    assert stricter.occupied.tolist() == [[False, False, True, False]] and stricter.unknown_cells is None
    with pytest.raises(SceneError, match='unknown of .* must be "occupied"'):
        image_from_entry({**entry, 'unknown': 'maybe'}, tmp_path)
    with pytest.raises(SceneError, match=r'free_thresh of .* must be a number in \[0, occupied_thresh'):
        image_from_entry({**entry, 'free_thresh': 0.9}, tmp_path)
