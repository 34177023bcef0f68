"""The Robotarium scenes package: its files are the scenes robotarium_exp.scene adds to the paper's, each a
declaration (a tube and a [robotarium] table) loading by name with the text of its file."""

from __future__ import annotations

import sys
from importlib import resources

import robotarium_exp.scenes
from robotarium_exp.scene import TABLE, list_scenes, load_scene
from vtube_planning.geometry import scene as planning_scenes

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib


def test_the_shipped_files_are_the_robotarium_scenes_and_load_by_name() -> None:
    files = {p.name: p for p in resources.files(robotarium_exp.scenes).iterdir() if p.name.endswith('.toml')}
    names = sorted(f.removesuffix('.toml') for f in files)
    assert names == sorted(set(list_scenes()) - set(planning_scenes.list_scenes()))
    for name in names:
        text = files[f'{name}.toml'].read_text(encoding='utf-8')
        assert set(tomllib.loads(text)[TABLE]) == {'n_robots'}
        scene = load_scene(name)
        assert scene.name == name and scene.text == text and scene.testbed == 'robotarium'
