"""``vtube scene list|show|export``: the shipped scenes, a summary and figure, a copy to edit; bad scenes refused."""

from __future__ import annotations

from pathlib import Path

import pytest

from robotarium_exp.fit import robotarium_fit
from robotarium_exp.scene import list_scenes, load_scene, shipped_scene_text
from tests.support.scenes import LINE_SCENE
from vtube.cli.app import main
from vtube.cli.scene import SceneExported, SceneList, SceneShown, export_view, list_view, show_view

BAD = {
    'missing_field': LINE_SCENE.replace('start_m = 2.0\n', ''),
    'negative_width': LINE_SCENE.replace('start_m = 2.0', 'start_m = -2.0'),
    'self_intersecting': LINE_SCENE.replace(
        '{ kind = "line", length_m = 10.0 }',
        '{ kind = "line", length_m = 10.0 }, { kind = "arc", radius_m = 3.0, angle_deg = 300.0 }, '
        '{ kind = "line", length_m = 10.0 }',
    ),
    'over_curved': LINE_SCENE.replace(
        '{ kind = "line", length_m = 10.0 }', '{ kind = "arc", radius_m = 1.0, angle_deg = 90.0 }'
    ),
    'unknown_key': LINE_SCENE + '[swarm]\nspeed = 3\n',
    'not_toml': LINE_SCENE + '[swarm\n',
}
BAD_MESSAGES = {
    'missing_field': "missing field 'start_m'",
    'negative_width': 'must be finite and > 0; got -2.0',
    'self_intersecting': 'overlaps itself',
    'over_curved': 'over-curved at l = 0.000 m',
    'unknown_key': "unknown key 'speed' in [swarm]",
    'not_toml': 'not valid TOML',
}


def test_scene_list_prints_every_shipped_scene(capsys) -> None:
    assert main(['scene', 'list']) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == list_scenes()


def test_the_list_view_aligns_name_length_and_title() -> None:
    view = list_view(SceneList((('A', 60.0, 'rapid'), ('robotarium_curve', 3.5, 'a bend'))))
    assert view.lines == ('A                        60.00 m  rapid', 'robotarium_curve          3.50 m  a bend')


def test_scene_show_prints_summary_and_writes_figure(tmp_path, capsys) -> None:
    out = tmp_path / 'figs' / 'A.png'
    assert main(['scene', 'show', 'A', '--out', str(out)]) == 0
    text = capsys.readouterr().out
    assert 'length                60.000 m' in text and 'a_rho = 0.5524' in text
    assert f'figure                {out}' in text and 'vtube scene export A FILE.toml writes a copy' in text
    data = out.read_bytes()
    assert data[:8] == b'\x89PNG\r\n\x1a\n' and len(data) > 20_000


def test_the_show_view_of_a_user_file_has_no_export_hint_and_no_figure(tmp_path) -> None:
    path = tmp_path / 'mine.toml'
    path.write_text(LINE_SCENE)
    scene = load_scene(path)
    view = show_view(SceneShown(scene, scene.tube.summary(), None, None))
    assert view.lines[0].startswith('scene mine: ') and f'  source                {path}' in view.lines
    assert '  half-width            2.000 .. 2.000 m' in view.lines and '  length                10.000 m' in view.lines
    assert not any('figure' in line or 'export' in line for line in view.lines)
    assert any(line.startswith('  swarm                 N = 20, v in [2, 5] m/s') for line in view.lines)


def test_scene_show_accepts_a_user_file(tmp_path, capsys) -> None:
    path = tmp_path / 'mine.toml'
    path.write_text(LINE_SCENE)
    assert main(['scene', 'show', str(path)]) == 0
    assert 'half-width            2.000 .. 2.000 m' in capsys.readouterr().out


@pytest.mark.parametrize('case', sorted(BAD))
def test_bad_scene_gives_exit_2_and_one_error_line(case: str, tmp_path, capsys) -> None:
    path = tmp_path / f'{case}.toml'
    path.write_text(BAD[case])
    assert main(['scene', 'show', str(path), '--out', str(tmp_path / 'x.png')]) == 2
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 1 and lines[0].startswith('error: ') and BAD_MESSAGES[case] in lines[0]
    assert str(path) in lines[0]  # the message names the file
    assert not (tmp_path / 'x.png').exists()


def test_unknown_scene_gives_exit_2(capsys) -> None:
    assert main(['scene', 'show', 'nowhere']) == 2
    assert capsys.readouterr().err.startswith("error: unknown scene 'nowhere'")


def test_a_shipped_scene_exported_is_the_same_scene_and_nothing_is_overwritten(tmp_path, capsys) -> None:
    path = tmp_path / 'deeper' / 'mine.toml'
    assert main(['scene', 'export', 'c', str(path)]) == 0
    assert capsys.readouterr().out == export_view(SceneExported('C', path)).lines[0] + '\n'
    mine, shipped = load_scene(path), load_scene('C')
    assert mine.tube.fingerprint() == shipped.tube.fingerprint() and mine.swarm == shipped.swarm
    assert (mine.planning, mine.control) == (shipped.planning, shipped.control)
    path.write_text('edited', encoding='utf-8')
    assert main(['scene', 'export', 'C', str(path)]) == 2
    assert 'exists; give another file name' in capsys.readouterr().err and path.read_text() == 'edited'


def test_the_export_view_says_where_and_what_next() -> None:
    view = export_view(SceneExported('C', Path('x/c.toml')))
    assert view.lines == ('scene C written to x/c.toml; edit it and pass the file where a scene is asked for',)


def robotarium_file(tmp_path: Path, name: str, n_robots: int) -> Path:
    """A copy of a shipped Robotarium scene declaring ``n_robots``."""
    _, text = shipped_scene_text(name)
    path = tmp_path / f'{name}_{n_robots}.toml'
    path.write_text(text.replace('n_robots = 6', f'n_robots = {n_robots}'), encoding='utf-8')
    return path


def test_scene_show_of_a_fitting_robotarium_scene_prints_its_derivations_and_exits_0(capsys) -> None:
    assert main(['scene', 'show', 'robotarium_trapezoid']) == 0
    lines = capsys.readouterr().out.splitlines()
    assert '  values of the [robotarium] declaration (set in the file or derived, and why):' in lines
    assert any(line.split()[:2] == ['rho_d_per_m2', '6.0'] for line in lines)
    assert lines[-1] == '  Robotarium            fits the Robotarium'


def test_scene_show_of_a_misfit_exits_1_with_every_reason(tmp_path, capsys) -> None:
    path = robotarium_file(tmp_path, 'robotarium_curve', 16)  # outside the start box and into the narrowing
    fit = robotarium_fit(load_scene(path))
    assert len(fit.misfits) >= 2
    assert main(['scene', 'show', str(path)]) == 1
    captured = capsys.readouterr()
    lines = captured.out.splitlines()
    assert f'  Robotarium            {fit.reason}' in lines and fit.reason.startswith('does not fit the Robotarium: ')
    assert [line for line in lines if 'also: ' in line] == [
        f'                        also: {m}' for m in fit.misfits[1:]
    ]
    assert captured.err == ''


def test_the_show_view_of_a_misfit_carries_exit_1() -> None:
    scene = load_scene('robotarium_trapezoid', n_robots=13)
    fit = robotarium_fit(scene)
    view = show_view(SceneShown(scene, scene.tube.summary(), fit, None))
    verdict = view.lines.index(f'  Robotarium            {fit.reason}')
    assert view.exit_code == 1 and view.lines[verdict + 1].strip().startswith('also: parking slot 12')
    # 5 rows of up to 3 from l = 0.12 m, 0.4 m apart: four end before the narrowing at 1.4 m, the fifth does not
    assert 'use at most 12 robots' in view.lines[verdict]
