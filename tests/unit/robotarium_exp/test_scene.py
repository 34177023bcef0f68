"""Robotarium scenes declared by intent: the shipped declarations give the values the hand-written files had (but
the look-ahead, which now covers the narrowing and the whole formation), the file's own values win and say so, N re-derives what depends on it, bad declarations are refused with the fix."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from robotarium_exp.scene import list_scenes, load_scene, shipped_scene_text
from robotarium_exp.spec import ROBOTARIUM
from tests.support.scenes import LINE_SCENE
from vtube_planning.errors import SceneError
from vtube_planning.geometry import scene as planning_scenes
from vtube_planning.geometry.scene import Workspace
from vtube_planning.params import ControlParams, PlanningOptions, SwarmParams

# The values of the hand-written files these declarations replace (git show
# d20cf38:vtube_planning/scenes/robotarium_trapezoid.toml and ..._curve.toml), derived by hand in their descriptions.
FORMER_SWARM = {
    'n_robots': 6,
    'v_min_mps': 0.04,
    'v_max_mps': 0.12,
    'a_v_mps2': 0.02,
    'a_n_mps2': 0.02,
    'r_p_m': 0.07,
    'r_s_m': 0.10,
    'r_a_m': 0.30,
    'rho_max_per_m2': 15.92,
}
FORMER_LOOKAHEAD_M = 0.7
FORMER_PLANNING = {'predictive_model': 'local_width', 'lookahead_m': FORMER_LOOKAHEAD_M}
# The one documented difference: the former files looked 0.7 m ahead (the 0.5 m narrowing plus half the 0.4 m
# formation); the declarations look as far as the narrowing (0.5 m) plus the whole formation (2 rows 0.4 m apart)
# plus two interaction bands (r_s + r_a = 0.4 m each): robotarium_exp.design.look_ahead.
LOOKAHEAD_M = 0.5 + 0.4 + 2 * 0.4


def expected_look_ahead(narrowing_m: float, formation_m: float) -> float:
    """The design's rule, written out: the narrowing plus the formation plus two bands (0.4 m each), to 5 cm."""
    return round((narrowing_m + formation_m + 0.8) / 0.05) * 0.05


FORMER_CONTROL = ControlParams(
    avoidance_gain=5e-4, keeping_gain=5e-4, k_ra_m3ps=0.02, r_a_max_m=0.5, feedforward=True, plan_at='center'
)
FORMER_DENSITY = {'robotarium_trapezoid': 6.0, 'robotarium_curve': 5.86}  # rho_d = rho0
FORMER_GRID = {'robotarium_trapezoid': 0.0125, 'robotarium_curve': 0.01}
TRAPEZOID_TUBE = """
[tube.center]
start_xy_m = [-1.45, 0.0]
pieces = [{ kind = "line", length_m = 2.45 }]

[tube.width]
start_m = 0.5
parts = [
    { kind = "constant", length_m = 1.4 },
    { kind = "linear", length_m = 0.5, to_m = 0.25, corner_m = 0.06 },
    { kind = "constant" },
]
"""


def write(tmp_path: Path, text: str, name: str = 'mine') -> Path:
    path = tmp_path / f'{name}.toml'
    path.write_text(text, encoding='utf-8')
    return path


@pytest.mark.parametrize('name', sorted(FORMER_DENSITY))
def test_the_shipped_declarations_give_the_former_files_values(name: str) -> None:
    scene = load_scene(name)
    rho = FORMER_DENSITY[name]
    assert scene.swarm == SwarmParams(**FORMER_SWARM, rho_d_per_m2=rho)
    assert scene.planning.lookahead_m == pytest.approx(LOOKAHEAD_M)  # to 5 cm: the curve's rows spread a little
    former = replace(scene.planning, lookahead_m=FORMER_LOOKAHEAD_M)
    assert former == PlanningOptions(**FORMER_PLANNING, rho0_per_m2=rho, grid_step_m=FORMER_GRID[name])
    # the former files' control values, the fitted testbed's delay and lag compensated (issue 32), and the density
    # tracked along the tube (issue 50)
    former = replace(FORMER_CONTROL, compensate_delay_steps=5.0, compensate_lag_s=0.19, stretch_gain_mps=0.3)
    assert scene.control == former
    assert scene.testbed == 'robotarium' and scene.source == f'<shipped>/{name}.toml'
    # the arena; the former files kept 0.1 m to its edge, the declaration the spec's margin (both tubes keep 0.1 m)
    assert scene.workspace == Workspace(*ROBOTARIUM.arena_m, margin_m=ROBOTARIUM.arena_margin_m)
    assert all(d.reason for d in scene.derived)
    given = {d.name for d in scene.derived if d.given}
    assert given == ({'grid_step_m'} if name == 'robotarium_curve' else set())


def test_the_derivations_say_why() -> None:
    derived = {d.name: d for d in load_scene('robotarium_trapezoid').derived}
    assert derived['n_robots'].reason == '[robotarium] n_robots'
    assert derived['rho_d_per_m2'].reason.startswith('the start formation (2 row(s) of up to 3, 0.40 m long)')
    assert derived['lookahead_m'].reason.startswith(
        'the narrowing from l = 1.40 m (0.50 m) plus the formation (0.40 m) plus 2 bands (0.4 m each)'
    )
    assert derived['r_a_m'].reason.startswith('r_s + r_a = 0.4 m')
    grid = {d.name: d for d in load_scene('robotarium_curve').derived}['grid_step_m']
    assert grid.value == 0.01 and grid.reason.startswith('set in the file (derived: 0.0125, ')


def test_a_value_in_the_file_overrides_and_is_reported_given(tmp_path: Path) -> None:
    text = (
        TRAPEZOID_TUBE + '[robotarium]\nn_robots = 6\n[swarm]\nv_max_mps = 0.1\nrho_d_per_m2 = 5.0\n'
        '[planning]\nlookahead_m = 1.1\n[control]\nk_ra_m3ps = 0.03\n'
    )
    scene, shipped = load_scene(write(tmp_path, text)), load_scene('robotarium_trapezoid')
    assert scene.swarm == replace(shipped.swarm, v_max_mps=0.1, rho_d_per_m2=5.0)
    assert scene.planning == replace(shipped.planning, lookahead_m=1.1)  # rho0 stays the formation's 6.0
    assert scene.control == replace(shipped.control, k_ra_m3ps=0.03)
    given = {d.name: d for d in scene.derived if d.given}
    assert sorted(given) == ['k_ra_m3ps', 'lookahead_m', 'rho_d_per_m2', 'v_max_mps']
    assert given['v_max_mps'].value == 0.1 and given['v_max_mps'].reason.startswith('set in the file (derived: 0.12, ')
    derived = expected_look_ahead(0.5, 0.4)  # the 2 x 3 formation, 0.4 m long
    assert given['lookahead_m'].value == 1.1
    assert given['lookahead_m'].reason.startswith(
        f'set in the file (derived: {derived:g}, the narrowing from l = 1.40 m'
    )


@pytest.mark.parametrize('n', [1, 3, 4, 9])
def test_n_robots_re_derives_density_and_look_ahead(n: int) -> None:
    """On the trapezoid: rows of 3 spaced 0.4 m, half-width 0.5 m, r_a = 0.3 m before a 0.5 m narrowing:
    rho = N / (2 lambda (span + 2 r_a)); look-ahead = 0.5 m + the span, at least the band 0.4 m (to 5 cm)."""
    scene = load_scene('robotarium_trapezoid', n_robots=n)
    span = 0.4 * ((n + 2) // 3 - 1)
    assert scene.swarm.n_robots == n
    assert scene.swarm.rho_d_per_m2 == scene.planning.rho0_per_m2 == round(n / (2 * 0.5 * (span + 0.6)), 2)
    assert scene.planning.lookahead_m == pytest.approx(expected_look_ahead(0.5, span))
    assert scene.swarm.r_s_m + scene.swarm.r_a_m == pytest.approx(0.4)
    assert {d.name: d.value for d in scene.derived}['n_robots'] == n


def test_n_robots_in_the_file_and_by_keyword(tmp_path: Path) -> None:
    path = write(tmp_path, TRAPEZOID_TUBE + '[robotarium]\nn_robots = 9\n')
    assert load_scene(path).swarm == load_scene('robotarium_trapezoid', n_robots=9).swarm
    assert load_scene(path, n_robots=4).swarm.n_robots == 4
    with pytest.raises(
        SceneError, match=r'n_robots can be changed only in a Robotarium scene \(one with a \[robotarium\]'
    ):
        load_scene('A', n_robots=4)


@pytest.mark.parametrize(
    ('table', 'message'),
    [
        ('n_robots = 6\nspeed = 1', r'\[robotarium\] takes exactly one key, n_robots \(1 to 20\); got '),
        ('', r'\[robotarium\] takes exactly one key, n_robots \(1 to 20\); got \{\}'),
        ('n_robots = 0', r'n_robots in \[robotarium\] must be a whole number >= 1 \(the testbed has 20\); got 0\.'),
        ('n_robots = "6"', r"must be a whole number >= 1 \(the testbed has 20\); got '6'\."),
        ('n_robots = true', r'must be a whole number >= 1 \(the testbed has 20\); got True\.'),
        ('n_robots = 6.0', r'must be a whole number >= 1 \(the testbed has 20\); got 6\.0\.'),
    ],
    ids=['unknown_key', 'empty', 'zero', 'string', 'bool', 'float'],
)
def test_a_bad_robotarium_table_is_refused_naming_the_file_and_the_fix(
    tmp_path: Path, table: str, message: str
) -> None:
    path = write(tmp_path, TRAPEZOID_TUBE + f'[robotarium]\n{table}\n')
    with pytest.raises(SceneError, match=message) as raised:
        load_scene(path)
    assert str(raised.value).startswith(f'{path}: ')


def test_a_robotarium_key_that_is_not_a_table_and_a_bad_keyword(tmp_path: Path) -> None:
    path = write(tmp_path, 'robotarium = 6\n' + TRAPEZOID_TUBE)
    with pytest.raises(SceneError, match=r'takes exactly one key, n_robots \(1 to 20\); got 6\.'):
        load_scene(path)
    with pytest.raises(SceneError, match=r'must be a whole number >= 1 .*; got 0\.'):
        load_scene('robotarium_curve', n_robots=0)


def test_a_scene_without_a_robotarium_table_loads_as_the_planning_package_does(tmp_path: Path) -> None:
    path = write(tmp_path, LINE_SCENE)
    for ours, theirs in (
        (load_scene('A'), planning_scenes.load_scene('A')),
        (load_scene(path), planning_scenes.load_scene(path)),
    ):
        assert ours.testbed is None and ours.derived == ()
        assert ours.tube.fingerprint() == theirs.tube.fingerprint()
        assert replace(ours, tube=theirs.tube) == theirs


def test_list_scenes_has_the_papers_and_the_robotariums() -> None:
    assert list_scenes() == [
        'A',
        'B',
        'C',
        'D',
        'robotarium_curve',
        'robotarium_curve_20',
        'robotarium_trapezoid',
        'robotarium_trapezoid_20',
    ]


@pytest.mark.parametrize('name', ['A', 'robotarium_trapezoid', 'robotarium_curve'])
def test_a_shipped_scenes_text_round_trips(tmp_path: Path, name: str) -> None:
    spelled, text = shipped_scene_text(name.upper())
    assert spelled == name
    copy, shipped = load_scene(write(tmp_path, text, name)), load_scene(name)
    assert copy.text == shipped.text == text
    assert copy.tube.fingerprint() == shipped.tube.fingerprint()
    assert (copy.swarm, copy.planning, copy.control, copy.workspace) == (
        shipped.swarm,
        shipped.planning,
        shipped.control,
        shipped.workspace,
    )
    assert copy.derived == shipped.derived and copy.testbed == shipped.testbed


def test_an_unknown_scene_lists_the_shipped_ones() -> None:
    with pytest.raises(
        SceneError, match=r"unknown scene 'nowhere'; shipped scenes are \['A', .*'robotarium_trapezoid_20'\]"
    ):
        shipped_scene_text('nowhere')
    with pytest.raises(SceneError, match="unknown scene 'nowhere'"):
        load_scene('nowhere')


def test_without_a_formation_the_density_is_n_abreast_and_the_look_ahead_two_bands(tmp_path: Path) -> None:
    """A tube hugging the arena's top edge (no cross-section in the start box), constant width: N robots abreast at
    the entrance, padded by r_a, capped at rho_max; no narrowing and no formation: two bands (0.8 m)."""
    text = '[tube.center]\nstart_xy_m = [-1.45, 0.88]\npieces = [{ kind = "line", length_m = 2.4 }]\n'
    text += '[tube.width]\nstart_m = 0.3\nparts = [{ kind = "constant" }]\n[robotarium]\nn_robots = 2\n'
    scene = load_scene(write(tmp_path, text))
    derived = {d.name: d for d in scene.derived}
    assert scene.swarm.rho_d_per_m2 == round(2 / (2 * 0.3 * 2 * 0.3), 2)  # 5.56, below rho_max
    assert derived['rho_d_per_m2'].reason.startswith('no start formation (no cross-section of the tube lies inside')
    assert scene.planning.lookahead_m == 0.8
    assert derived['lookahead_m'].reason.startswith(
        'no narrowing plus the formation (0.00 m) plus 2 bands (0.4 m each)'
    )
