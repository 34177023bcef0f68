"""The scenes package: the shipped scene files are exactly the scenes list_scenes names, each loading by name
with the text of its file."""

from __future__ import annotations

from importlib import resources

import vtube_planning.scenes
from vtube_planning.geometry.scene import list_scenes, load_scene


def test_the_shipped_files_are_the_listed_scenes_and_load_by_name() -> None:
    files = {p.name for p in resources.files(vtube_planning.scenes).iterdir() if p.name.endswith('.toml')}
    assert sorted(f.removesuffix('.toml') for f in files) == sorted(list_scenes())
    text = resources.files(vtube_planning.scenes).joinpath('C.toml').read_text(encoding='utf-8')
    scene = load_scene('C')
    assert scene.name == 'C' and scene.text == text
