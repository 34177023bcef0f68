"""``vtube tube generate``: a map file in, a scene file out that every command takes; refusals exit 2."""

from __future__ import annotations

from pathlib import Path

from tests.unit.vtube_planning.geometry.test_generate import MAP_FILE
from vtube.cli.app import main
from vtube.cli.tube import COMMAND


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
