"""Tube generation from an obstacle map: a certified, regular tube through the passage, checked independently at
1 cm; refusals that name the place and the reason; seeded random maps; the map file and its round trip."""

from __future__ import annotations

import numpy as np
import pytest

from tests.support.tube_clearance import closest_approach
from vtube_planning.errors import SceneError
from vtube_planning.geometry.from_maps.centre_path import CornerError
from vtube_planning.geometry.from_maps.generate import LEADS, TubeGenerationError, TubeSpec, generate_tube
from vtube_planning.geometry.from_maps.map_file import generated_scene
from vtube_planning.geometry.obstacles import Disc, Obstacles, Polygon
from vtube_planning.geometry.scene import scene_from_text
from vtube_planning.geometry.workspace import Workspace

MAP = Workspace(0.0, 20.0, 0.0, 10.0, margin_m=0.2)


def wall_with_gap(gap_low: float, gap_high: float) -> Obstacles:
    """A wall across the map at x in [9, 11] with a gap between y = gap_low and y = gap_high."""
    return Obstacles(
        polygons=(
            Polygon(((9.0, 0.0), (11.0, 0.0), (11.0, gap_low), (9.0, gap_low))),
            Polygon(((9.0, gap_high), (11.0, gap_high), (11.0, 10.0), (9.0, 10.0))),
        )
    )


def spec(obstacles: Obstacles, **options: float) -> TubeSpec:
    values = {'half_width_min_m': 0.5, 'half_width_max_m': 2.0, 'margin_m': 0.1, 'resolution_m': 0.1, **options}
    return TubeSpec(MAP, obstacles, (1.0, 2.0), (19.0, 8.0), **values)  # type: ignore[arg-type]


def assert_misses(tube, obstacles: Obstacles, margin_m: float, step_m: float = 0.01, across: int = 101) -> None:
    """No sampled point of the tube within ``margin_m`` of an obstacle (:mod:`tests.support.tube_clearance`)."""
    assert closest_approach(tube, obstacles, step_m, across) >= margin_m - 1e-9


def test_the_tube_threads_the_gap_regular_and_clear() -> None:
    obstacles = wall_with_gap(4.0, 7.0)  # 3 m gap: room 1.5 m around its middle line y = 5.5
    made = generate_tube(spec(obstacles))
    tube = made.tube
    assert made.certificate.clear
    assert np.allclose(tube.center_at(np.array([0.0]))[0], [1.0, 2.0])
    assert np.allclose(tube.center_at(np.array([tube.length_m]))[0], [19.0, 8.0], atol=1e-9)
    at_wall = tube.project(np.array([[10.0], [5.5]]))
    assert abs(float(at_wall.y_m[0])) < 1.0  # through the gap
    l_m = np.linspace(0.0, tube.length_m, 20001)
    half = tube.half_width(l_m)
    assert half.min() >= 0.5 - 1e-12 and half.max() <= 2.0 + 1e-12
    assert np.max(half * np.abs(tube.curvature(l_m))) <= 0.8 + 1e-9  # curvature_share
    assert tube.width.max_abs_slope() <= 0.3 + 1e-12
    assert_misses(tube, obstacles, 0.1)
    left, right = tube.boundaries(l_m)
    for side in (left, right):
        assert np.all(MAP.clearance(side) >= MAP.margin_m - 1e-9)


def test_a_gap_too_narrow_is_refused_with_the_widest_passage() -> None:
    with pytest.raises(TubeGenerationError, match=r'no passage .* the widest has about 0\.[345]\d\d m') as refused:
        generate_tube(spec(wall_with_gap(4.0, 4.8)))  # room 0.4 m (reported to the grid's 0.1 m); 0.69 m needed
    assert 'lower half_width_min_m or margin_m, or move an obstacle' in str(refused.value)


def test_a_start_inside_an_obstacle_or_a_tight_turn_is_refused_with_its_place() -> None:
    blocked = Obstacles((Disc((1.0, 2.0), 0.3),))
    with pytest.raises(TubeGenerationError, match=r'the start \(1\.000, 2\.000\) has 0\.000 m of room .* move it'):
        generate_tube(spec(blocked))
    # a zigzag through two offset gaps forces turns sharper than a 20 m radius allows
    zigzag = Obstacles(
        polygons=(
            Polygon(((6.0, 0.0), (7.0, 0.0), (7.0, 7.0), (6.0, 7.0))),
            Polygon(((13.0, 3.0), (14.0, 3.0), (14.0, 10.0), (13.0, 10.0))),
        )
    )
    with pytest.raises(
        TubeGenerationError,
        match=r'the turn of \d+ degrees at \(\d+\.\d+, \d+\.\d+\) cannot be rounded with turn_radius_min_m = 20.0',
    ):
        generate_tube(spec(zigzag, turn_radius_min_m=20.0))
    made = generate_tube(spec(zigzag, turn_radius_min_m=0.5))  # a gentler limit threads it
    assert_misses(made.tube, zigzag, 0.1)


@pytest.mark.parametrize('seed', range(8))
def test_seeded_random_forests_give_a_clear_tube_or_a_refusal(seed: int) -> None:
    rng = np.random.default_rng(seed)
    discs = tuple(
        Disc((float(x), float(y)), float(r))
        for x, y, r in zip(rng.uniform(3, 17, 12), rng.uniform(0, 10, 12), rng.uniform(0.3, 1.2, 12), strict=True)
    )
    obstacles = Obstacles(discs)
    try:
        made = generate_tube(spec(obstacles, half_width_min_m=0.3))
    except TubeGenerationError as err:
        assert str(err)  # a refusal says why
        return
    assert made.certificate.clear
    assert_misses(made.tube, obstacles, 0.1)


MAP_FILE = """
title = "Gap"

[tube.generate]
start_m = [1.0, 2.0]
goal_m = [19.0, 8.0]
half_width_min_m = 0.5
half_width_max_m = 2.0
margin_m = 0.1

[workspace]
x_min_m = 0.0
x_max_m = 20.0
y_min_m = 0.0
y_max_m = 10.0
margin_m = 0.2

[obstacles]
polygons = [
    { vertices_m = [[9.0, 0.0], [11.0, 0.0], [11.0, 4.0], [9.0, 4.0]] },
    { vertices_m = [[9.0, 7.0], [11.0, 7.0], [11.0, 10.0], [9.0, 10.0]] },
]

[swarm]
v_min_mps = 1.0
"""


def test_the_map_file_becomes_a_scene_that_loads_to_the_same_tube() -> None:
    text, made = generated_scene(MAP_FILE, 'gap.toml')
    assert '\n[tube.generate]' not in text and '\n[tube.center]' in text and '\n[obstacles]' in text
    assert text.index('[tube.center]') > text.index('title = "Gap"')  # in place of [tube.generate]
    assert 'turn_radius_min_m = 1.0' in text  # v_min^2 / a_n from [swarm]: 1^2 / 1
    scene = scene_from_text(text, name='gap', source='gap_scene.toml')
    l_m = np.linspace(0.0, made.tube.length_m, 5001)
    assert scene.tube.length_m == pytest.approx(made.tube.length_m, rel=1e-12)
    np.testing.assert_allclose(scene.tube.center_at(l_m), made.tube.center_at(l_m), atol=1e-9)
    np.testing.assert_allclose(scene.tube.half_width(l_m), made.tube.half_width(l_m), atol=1e-12)
    assert len(scene.obstacles.polygons) == 2 and scene.swarm.v_min_mps == 1.0


def test_map_file_errors_name_the_fix() -> None:
    with pytest.raises(SceneError, match=r"give one of 'goal_m' \(\[x, y\]\) and 'goal_region_m'"):
        generated_scene(MAP_FILE.replace('goal_m = [19.0, 8.0]\n', ''), 'gap.toml')
    with pytest.raises(SceneError, match=r"unknown key 'width_m' in \[tube.generate\]"):
        generated_scene(MAP_FILE.replace('margin_m = 0.1\n', 'width_m = 0.1\n', 1), 'gap.toml')
    with pytest.raises(SceneError, match=r'a map file needs \[workspace\]'):
        generated_scene(MAP_FILE.split('[workspace]')[0], 'gap.toml')
    with pytest.raises(SceneError, match=r'half_width_min_m must be a finite number > 0'):
        generated_scene(MAP_FILE.replace('half_width_min_m = 0.5', 'half_width_min_m = -0.5'), 'gap.toml')
    with pytest.raises(SceneError, match=r'a Robotarium map file needs turn_radius_min_m in \[tube.generate\]'):
        generated_scene(MAP_FILE + '\n[robotarium]\nn_robots = 6\n', 'gap.toml')  # no silent 4 m turns in the arena


def test_a_heading_without_a_lead_gets_the_shortest_lead_that_fits() -> None:
    """Issue 49: a heading without lead_m ended in "radius 0.000 m". The lead is fitted: the shortest of LEADS (in
    turn radii) whose tube holds the heading, 2 lead_m straight and the turn off it no tighter than the limit."""
    obstacles = wall_with_gap(4.0, 7.0)
    made = generate_tube(spec(obstacles, start_heading_deg=90.0, turn_radius_min_m=1.0))  # up, then right
    assert made.lead_m in [factor * 1.0 for factor in LEADS] and made.certificate.clear
    assert np.allclose(made.tube.tangent(0.0), [0.0, 1.0]) and np.allclose(made.tube.curvature(np.array([0.0])), 0.0)
    shorter = [factor * 1.0 for factor in LEADS if factor * 1.0 < made.lead_m]
    for lead in shorter:  # each shorter lead is refused when given
        with pytest.raises(TubeGenerationError):
            generate_tube(spec(obstacles, start_heading_deg=90.0, turn_radius_min_m=1.0, lead_m=lead))
    l_m = np.linspace(0.0, made.tube.length_m, 4001)
    assert np.max(np.abs(made.tube.curvature(l_m))) <= 1.0 + 1e-9
    assert made.lead_m == generate_tube(spec(obstacles, start_heading_deg=90.0, turn_radius_min_m=1.0)).lead_m
    assert generate_tube(spec(obstacles)).lead_m == 0.0  # no heading: no lead


def test_a_tight_corner_is_routed_around_another_way(monkeypatch) -> None:
    """Issue 49: a corner no arc rounds was refused where another route had room (between other discs, or wider of
    the same one); the corner is taken out of the grid and the route searched again. On this seeded forest the
    cheapest route's corners cannot be rounded with a 3 m radius; another route's can."""
    from vtube_planning.geometry.from_maps import generate

    rng = np.random.default_rng(6)
    discs = tuple(
        Disc((float(x), float(y)), float(r))
        for x, y, r in zip(rng.uniform(3, 17, 12), rng.uniform(0, 10, 12), rng.uniform(0.3, 1.2, 12), strict=True)
    )
    obstacles = Obstacles(discs)
    tight = spec(obstacles, half_width_min_m=0.3, turn_radius_min_m=3.0)
    monkeypatch.setattr(generate, 'ROUTES', 1)
    with pytest.raises(CornerError, match='cannot be rounded with turn_radius_min_m = 3.0'):
        generate_tube(tight)  # the cheapest route alone: refused at a corner
    monkeypatch.undo()
    made = generate_tube(tight)
    assert made.certificate.clear
    assert_misses(made.tube, obstacles, 0.1)
    l_m = np.linspace(0.0, made.tube.length_m, 4001)
    assert np.max(np.abs(made.tube.curvature(l_m))) <= 1.0 / 3.0 + 1e-9


def test_headings_at_the_ends_are_held_straight_for_the_lead() -> None:
    obstacles = wall_with_gap(4.0, 7.0)
    made = generate_tube(spec(obstacles, start_heading_deg=0.0, goal_heading_deg=90.0, lead_m=1.0))
    tube, pieces = made.tube, made.tube.center.pieces
    assert pieces[0].radius_m is None and pieces[0].length_m >= 1.0 - 1e-9
    assert pieces[-1].radius_m is None and pieces[-1].length_m >= 1.0 - 1e-9
    np.testing.assert_allclose(tube.tangent(np.array([0.0, tube.length_m])), [[1.0, 0.0], [0.0, 1.0]], atol=1e-9)
    assert_misses(tube, obstacles, 0.1, step_m=0.05, across=21)
    with pytest.raises(
        TubeGenerationError, match=r"the end of the start's straight lead \(1\.000, 0\.000\) lies outside"
    ):
        generate_tube(spec(obstacles, start_heading_deg=-90.0, lead_m=1.0))  # 2 m down from y = 2: off the map
    # a lead too short for its turn: its end turns by theta towards the goal, on an empty map, and half the lead's
    # 2 lead_m allows a radius of lead_m / tan(theta / 2); the turn needs lead_m >= r tan(theta / 2)
    half_turn = 0.5 * np.arctan2(8.0 - 2.0, 19.0 - 1.5)
    with pytest.raises(
        TubeGenerationError,
        match=rf'radius of {0.25 / np.tan(half_turn):.3f} m at most; lengthen lead_m beyond {2.0 * np.tan(half_turn):.2f} m',
    ):
        generate_tube(spec(Obstacles(), start_heading_deg=0.0, turn_radius_min_m=2.0, lead_m=0.25))
    with pytest.raises(TubeGenerationError, match='the straight lead from .* has too little room'):
        generate_tube(spec(obstacles, start_heading_deg=0.0, lead_m=5.5))  # 11 m along y = 2: through the wall


def test_an_end_given_as_a_region_is_the_node_the_cheapest_path_joins() -> None:
    """The start anywhere in x 1..3, y 1..9: the chosen node is, by a search back from the goal over the same
    graph (an independent recomputation), the cheapest of the region's free nodes; the tube then starts there."""
    from scipy.sparse import csgraph

    from vtube_planning.geometry.from_maps.centre_path import SearchGrid

    grid = SearchGrid(spec(wall_with_gap(4.0, 7.0)))
    start, goal = grid.cheapest_ends((1.0, 3.0, 1.0, 9.0), (19.0, 8.0))
    assert goal == (19.0, 8.0)  # a point end is kept
    index = np.arange(grid.free.size).reshape(grid.free.shape)
    goal_node = grid.node(goal, 'goal')
    back = csgraph.dijkstra(grid._graph((goal_node,)), directed=False, indices=int(index[goal_node]))
    region = grid._in_box((1.0, 3.0, 1.0, 9.0), 'start')
    chosen = int(index[np.abs(grid.x - start[0]).argmin(), np.abs(grid.y - start[1]).argmin()])
    assert region.flat[chosen] and back[chosen] == back[index[region]].min()
    text, made = generated_scene(
        MAP_FILE.replace('start_m = [1.0, 2.0]', 'start_region_m = [1.0, 3.0, 1.0, 9.0]'), 'g.toml'
    )
    assert np.allclose(made.tube.center_at(0.0), start) and 'start_m = [' in text  # the comment records the choice
    with pytest.raises(SceneError, match=r"give one of 'goal_m' \(\[x, y\]\) and 'goal_region_m'"):
        generated_scene(
            MAP_FILE.replace('goal_m = [19.0, 8.0]', 'goal_region_m = [18, 19, 7, 9]\ngoal_m = [19.0, 8.0]'), 'g.toml'
        )
    with pytest.raises(SceneError, match=r'start_region_m must be \[x_min, x_max, y_min, y_max\] with x_min <= x_max'):
        generated_scene(MAP_FILE.replace('start_m = [1.0, 2.0]', 'start_region_m = [3.0, 1.0, 1.0, 9.0]'), 'g.toml')
    with pytest.raises(TubeGenerationError, match='no point of the start region x 9..11, y 1..3 m has room'):
        grid.cheapest_ends((9.0, 11.0, 1.0, 3.0), goal)  # inside the wall
