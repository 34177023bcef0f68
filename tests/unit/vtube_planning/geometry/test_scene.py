"""Scene files: the shipped scenes and strict validation of user files."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.scene import load_scene
from vtube_planning.errors import SceneError
from vtube_planning.geometry.scene import list_scenes, scene_from_text
from vtube_planning.params import SwarmParams

ARENA = (-1.6, 1.6, -1.0, 1.0)  # Robotarium arena, docs/design.md
PAPER_SCENES = ('A', 'B', 'C', 'D')
ROBOTARIUM_SCENES = ('robotarium_curve', 'robotarium_curve_20', 'robotarium_trapezoid', 'robotarium_trapezoid_20')

VALID = """
title = "a user scene"
[tube.center]
pieces = [{ kind = "line", length_m = 10.0 }, { kind = "arc", radius_m = 8.0, angle_deg = -30.0 }]
[tube.width]
start_m = 2.0
parts = [{ kind = "constant", length_m = 4.0 }, { kind = "smooth", length_m = 3.0, to_m = 1.0 }, { kind = "constant" }]
[swarm]
n_robots = 12
[planning]
lookahead_m = 2.0
"""


def test_shipped_scenes_are_the_paper_cases_and_the_robotarium_scenes() -> None:
    """vtube_planning ships the paper's scenes; the Robotarium's are robotarium_exp's declarations."""
    from robotarium_exp.scene import list_scenes as every_scene

    assert list_scenes() == sorted(PAPER_SCENES)
    assert every_scene() == sorted(PAPER_SCENES + ROBOTARIUM_SCENES)


@pytest.mark.parametrize('name', PAPER_SCENES + ROBOTARIUM_SCENES)
def test_every_shipped_scene_loads_and_is_regular(name: str) -> None:
    scene = load_scene(name)
    summary = scene.tube.summary()
    assert summary['lambda_kappa_max'] < 1.0
    assert summary['half_width_min_m'] > 0.0
    assert scene.description and scene.title
    assert load_scene(name.lower()).tube.length_m == scene.tube.length_m  # names are case-insensitive


@pytest.mark.parametrize('name', ROBOTARIUM_SCENES)
def test_robotarium_scenes_stay_inside_the_arena_by_10_cm(name: str) -> None:
    tube = load_scene(name).tube
    l = np.linspace(0.0, tube.length_m, 20001)
    x_min, x_max, y_min, y_max = ARENA
    for side in tube.boundaries(l):
        assert side[:, 0].min() >= x_min + 0.1 and side[:, 0].max() <= x_max - 0.1
        assert side[:, 1].min() >= y_min + 0.1 and side[:, 1].max() <= y_max - 0.1


def test_paper_scenes_share_widths_and_differ_in_narrowing_rate() -> None:
    scenes = {n: load_scene(n) for n in PAPER_SCENES}
    for scene in scenes.values():
        assert scene.swarm == SwarmParams()  # Table 1
        assert scene.tube.length_m == pytest.approx(60.0, abs=1e-9)
        assert scene.tube.half_width(0.0) == 4.5 and scene.tube.half_width(60.0) == pytest.approx(1.2)
    l = np.linspace(0.0, 60.0, 6001)
    steepest = {n: np.abs(s.tube.half_width_slope(l)).max() for n, s in scenes.items()}
    assert steepest['C'] > 3 * steepest['A'] and steepest['D'] > 3 * steepest['B']  # rapid vs normal
    for n in ('A', 'C'):
        assert np.all(scenes[n].tube.curvature(l) == 0.0)  # trapezoids are straight
    for n in ('B', 'D'):
        assert np.abs(scenes[n].tube.curvature(l)).max() == pytest.approx(1 / 12.0)  # curves bind (p4)


def test_user_scene_file_by_path(tmp_path) -> None:
    path = tmp_path / 'mine.toml'
    path.write_text(VALID)
    scene = load_scene(path)
    assert scene.name == 'mine' and scene.swarm.n_robots == 12 and scene.planning.lookahead_m == 2.0
    assert scene.tube.length_m == pytest.approx(10.0 + 8.0 * np.pi / 6)
    assert scene.tube.half_width(scene.tube.length_m) == pytest.approx(1.0)  # last part filled the rest
    assert scene.tube.curvature(12.0) == pytest.approx(-1 / 8.0)


def test_waypoint_scene(tmp_path) -> None:
    text = VALID.replace(
        'pieces = [{ kind = "line", length_m = 10.0 }, { kind = "arc", radius_m = 8.0, angle_deg = -30.0 }]',
        'waypoints = [[0, 0], [5, 1], [10, 0], [15, -1]]',
    )
    scene = scene_from_text(text, name='w', source='w.toml')
    np.testing.assert_allclose(scene.tube.center_at(scene.tube.length_m), [15.0, -1.0], atol=1e-9)


@pytest.mark.parametrize(
    ('old', 'new', 'match'),
    [
        ('title = "a user scene"', 'titel = "x"', "unknown key 'titel' in the top level"),
        ('start_m = 2.0', 'start_m = 2.0\nwidht = 3', r"unknown key 'widht' in \[tube.width\]"),
        ('n_robots = 12', 'n_robot = 12', r"unknown key 'n_robot' in \[swarm\]; expected one of: n_robots"),
        ('lookahead_m = 2.0', 'look_ahead = 2.0', r"unknown key 'look_ahead' in \[planning\]"),
        (
            '{ kind = "constant", length_m = 4.0 }',
            '{ kind = "constant", length_m = 4.0, to = 1 }',
            r"unknown key 'to' in \[tube.width.parts\[0\]\]",
        ),
        ('start_m = 2.0\n', '', r"missing field 'start_m' in \[tube.width\]"),
        (
            '{ kind = "arc", radius_m = 8.0, angle_deg = -30.0 }',
            '{ kind = "arc", radius_m = 8.0 }',
            r"missing field 'angle_deg' in \[tube.center.pieces\[1\]\]",
        ),
        ('to_m = 1.0', 'to_m = -1.0', r'ends at to_m = -1.0 m at l = 7.000 m'),
        ('start_m = 2.0', 'start_m = -2.0', 'start_m .* must be finite and > 0; got -2.0'),
        ('radius_m = 8.0', 'radius_m = 0.9', r'over-curved at l = 10.000 m'),
        (
            '{ kind = "arc", radius_m = 8.0, angle_deg = -30.0 }',
            '{ kind = "arc", radius_m = 2.5, angle_deg = 300.0 }, { kind = "line", length_m = 10.0 }',
            'overlaps itself: the cross-sections at l = ',
        ),
        ('n_robots = 12', 'n_robots = 0', 'n_robots must be an integer >= 1'),
        ('lookahead_m = 2.0', 'lookahead_m = "far"', "lookahead_m must be a finite number > 0; got 'far'"),
        ('[tube.width]', '[tube.width]\n[tube.width.x]', r"unknown key 'x' in \[tube.width\]"),
        ('length_m = 4.0 }', 'length_m = 40.0 }', 'already cover 43.000 m of a 14.189 m tube'),
        ('[swarm]', '[swarm\n', 'not valid TOML'),
    ],
)
def test_bad_scene_raises_scene_error_naming_the_problem(old: str, new: str, match: str) -> None:
    assert old in VALID
    with pytest.raises(SceneError, match=match) as info:
        scene_from_text(VALID.replace(old, new, 1), name='bad', source='bad.toml')
    assert str(info.value).startswith('bad.toml: ')


def test_unknown_scene_name_lists_the_shipped_ones(tmp_path) -> None:
    with pytest.raises(SceneError, match=r"unknown scene 'E'; shipped scenes are \['A', 'B'"):
        load_scene('E')
    with pytest.raises(SceneError, match='does not exist'):
        load_scene(tmp_path / 'missing.toml')


def test_workspace_margin_is_enforced() -> None:
    text = VALID + '[workspace]\nx_min_m = -0.2\nx_max_m = 20.0\ny_min_m = -3.0\ny_max_m = 3.0\nmargin_m = 0.5\n'
    with pytest.raises(SceneError, match=r'boundary at l = 0.000 m, point \(0.000, .*less than margin_m = 0.5'):
        scene_from_text(text, name='ws', source='ws.toml')
    scene = scene_from_text(text.replace('x_min_m = -0.2', 'x_min_m = -1.5'), name='ws', source='ws.toml')
    assert scene.workspace is not None and scene.workspace.margin_m == 0.5
