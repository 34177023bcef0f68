"""Campaign files: expanded into runs with stable keys; bad campaigns refused before any run, the problem named."""

from __future__ import annotations

import hashlib
import json
import os
import re
from dataclasses import asdict, replace
from importlib import resources
from pathlib import Path

import pytest

from tests.support.campaigns import write
from vtube.cli import main
from vtube_planning.geometry.scene import load_scene
from vtube_planning.studies.campaign import Campaign, run_key
from vtube_planning.studies.campaign_store import RUNS_FILE
from vtube_planning.studies.study import Point, RunSettings

FAULTS = """
name = "faults"
[axes]
scene = ["C", "D"]
mode = ["planning", "no planning"]
seed = 3
pose_noise_m = [0.0, 0.02]
"""


def test_a_campaign_file_expands_into_runs_with_stable_keys(tmp_path) -> None:
    path = write(tmp_path, FAULTS)
    campaign = Campaign.from_toml(path)
    points = campaign.points()
    assert len(points) == 2 * 2 * 3 * 2
    assert {(p.n_robots, p.saturation) for p in points} == {
        (load_scene(s).swarm.n_robots, load_scene(s).control.saturation) for s in 'CD'
    }  # each scene's own N and saturation where the axes leave them out
    assert [p.seed for p in points[:6]] == [0, 0, 1, 1, 2, 2] and points[0].mode == 'planning'
    keys = [run_key(p, campaign.settings) for p in points]
    assert len(set(keys)) == len(keys)
    before = {
        k: v
        for k, v in asdict(points[0]).items()
        if k
        not in ('lag_s', 'compensation', 'map', 'map_seed', 'map_clutter', 'map_width_m', 'controller', 'narrowest_m')
    }  # axes added later
    text = json.dumps({'point': before, 'settings': asdict(campaign.settings)}, sort_keys=True)
    assert keys[0] == hashlib.sha256(text.encode()).hexdigest()[:16]  # tables written before keep their keys
    assert run_key(replace(points[0], compensation='known'), campaign.settings) not in keys
    assert keys == [run_key(p, campaign.settings) for p in Campaign.from_toml(path).points()]  # stable
    moved = write(tmp_path, FAULTS + '[settings]\nfailure_at = 0.25\n', 'moved.toml')
    assert not set(keys) & {run_key(p, RunSettings(failure_at=0.25)) for p in Campaign.from_toml(moved).points()}
    scene_file = write(tmp_path, resources.files('vtube_planning.scenes').joinpath('C.toml').read_text(), 'mine.toml')
    own = Campaign.from_toml(write(tmp_path, '[axes]\nscene = ["mine.toml"]\n', 'own.toml'))
    mine = load_scene(scene_file)
    assert own.points() == [Point('mine.toml', n_robots=mine.swarm.n_robots, saturation=mine.control.saturation)]
    assert own.runnable(own.points()[0]).scene == str(scene_file)  # named as in the file, loaded beside it
    maps = Campaign.from_toml(write(tmp_path, FAULTS + 'map = ["forest"]\nmap_seed = 2\n', 'maps.toml')).points()
    assert len(maps) == 2 * len(points) and {(p.map, p.map_seed) for p in maps} == {('forest', 0), ('forest', 1)}
    narrow = Campaign.from_toml(write(tmp_path, FAULTS + 'narrowest_m = [0.9, 1.5]\n', 'narrow.toml')).points()
    assert len(narrow) == 2 * len(points) and {p.narrowest_m for p in narrow} == {0.9, 1.5}
    assert not set(keys) & {run_key(p, campaign.settings) for p in narrow}  # a narrowed tube is another run


def test_fresh_seeds_to_confirm_are_run_in_every_grid_and_recorded() -> None:
    """confirm_seeds adds runs at those seeds (keys as any run's), is recorded only when given (older folders keep
    their campaign.json) and must not reuse a seed the grids run."""
    data = {'axes': {'scene': ['C'], 'mode': ['planning'], 'seed': 2}, 'confirm_seeds': [100, 101]}
    campaign = Campaign.from_dict(data)
    assert [p.seed for p in campaign.points()] == [0, 1, 100, 101] and campaign.confirm_seeds == (100, 101)
    assert Campaign.from_dict(campaign.to_json()) == campaign
    plain = Campaign.from_dict({k: v for k, v in data.items() if k != 'confirm_seeds'})
    assert 'confirm_seeds' not in plain.to_json() and plain.points() == campaign.points()[:2]
    with pytest.raises(ValueError, match=r'must be fresh seeds.*\[1\] are in both'):
        Campaign.from_dict(data | {'confirm_seeds': [1, 5]})


def test_families_and_held_out_are_read_checked_and_recorded() -> None:
    """[families] and held_out are read, recorded only when given, and checked against the campaign's modes,
    metrics and axes; held_out needs confirm seeds; the judging pools the seeds unless they are held out."""
    data = {'axes': {'scene': ['C'], 'mode': ['planning', 'no planning'], 'seed': 6}, 'confirm_seeds': [100, 101]}
    family = {'comparisons': ['planning - no planning'], 'metrics': ['passing_time_s'], 'pose_noise_m': [0.0]}
    campaign = Campaign.from_dict(data | {'families': {'faster': family}})
    assert campaign.to_json()['families'] == {'faster': family} and 'held_out' not in campaign.to_json()
    assert Campaign.from_dict(campaign.to_json()) == campaign and campaign.judging.held_out == ()
    held = Campaign.from_dict(data | {'held_out': True})
    assert held.to_json()['held_out'] is True and held.judging.held_out == (100, 101)
    assert 'families' not in held.to_json() and held.points() == campaign.points()
    wrong = {
        'planning - nothing': ({'comparisons': ['planning - nothing']}, 'is not a comparison "a - b" of two modes'),
        'metric': ({'metrics': ['fun']}, "families.f: unknown metric 'fun'"),
        'axis': ({'speed': [1.0]}, "families.f: unknown key 'speed'; a family has comparisons, metrics and scene"),
        'seed': ({'seed': [1]}, "families.f: unknown key 'seed'"),
        'value': ({'model': ['toy']}, "families.f: axes.model holds 'toy'"),
    }
    for spec, phrase in wrong.values():
        with pytest.raises(ValueError, match=re.escape(phrase)):
            Campaign.from_dict(data | {'families': {'f': spec}})
    with pytest.raises(ValueError, match='held_out = true needs seeds to hold out'):
        Campaign.from_dict({'axes': data['axes'], 'held_out': True})
    with pytest.raises(ValueError, match='held_out must be true or false'):
        Campaign.from_dict(data | {'held_out': 'yes'})


BAD_CAMPAIGNS = {
    'unknown axis': (FAULTS + 'speed = [1.0]\n', "unknown axis 'speed'; the axes are scene, map, map_seed"),
    'unknown metric': ('metrics = ["fun"]\n' + FAULTS, "unknown metric 'fun'; choose from passing_time_s"),
    'empty grid': (FAULTS.replace('seed = 3', 'seed = []'), 'axes.seed has no values, so the grid is empty'),
    'unknown mode': (FAULTS.replace('"no planning"', '"fast"'), "axes.mode holds 'fast'; choose from 'planning'"),
    'wrong type': (FAULTS.replace('0.02', '"high"'), "axes.pose_noise_m holds 'high'; its values must be floats"),
    'out of range': (FAULTS.replace('0.02', '-0.1'), 'axes.pose_noise_m holds -0.1; its values must be >= 0.0'),
    'unknown compensation': (
        FAULTS + 'compensation = ["maybe"]\n',
        "axes.compensation holds 'maybe'; choose from 'none', 'known', 'known-1', 'known+1'.",
    ),
    'negative lag': (FAULTS + 'lag_s = [-0.2]\n', 'axes.lag_s holds -0.2; its values must be >= 0.0'),
    'unknown scene': (FAULTS.replace('"D"', '"Z"'), "unknown scene 'Z'; shipped scenes are"),
    'unknown setting': (FAULTS + '[settings]\nspeed = 1\n', "unknown setting 'speed'; the settings are dt_s"),
    'bad setting': (FAULTS + '[settings]\nfailure_at = 2.0\n', 'settings.failure_at must be in [0, 1]'),
    'no scene': ('[axes]\nseed = 2\n', 'a grid names no scene: give axes.scene'),
    'no such robot': (
        FAULTS + 'failure = ["stop"]\n[settings]\nfailure_robot = 20\n',
        'does not exist in a swarm of 20',
    ),
    'not TOML': (FAULTS + '[axes\n', 'not a valid TOML file'),
    'unknown map': (FAULTS + 'map = ["maze"]\n', "axes.map holds 'maze'; choose from 'none', 'forest', 'blocks'"),
    'opening too wide': (
        FAULTS + 'map = ["bottleneck"]\nmap_width_m = [30.0]\n',
        'axes.map_width_m holds 30.0; its values must be in [1, 20] m',
    ),
    'no map seed': (FAULTS + 'map = ["forest"]\nmap_seed = 0\n', 'axes.map_seed = 0 runs no seed'),
    'seeds backwards': (
        FAULTS.replace('seed = 3', 'seed = "19-10"'),
        "axes.seed = '19-10': the range '19-10' runs backwards; write it first to last, like 10-19.",
    ),
    'seed twice': (FAULTS.replace('seed = 3', 'seed = "0-4,3"'), "axes.seed = '0-4,3': seed 3 is given twice"),
}


def test_the_seeds_of_a_campaign_may_be_a_range_or_a_list_in_a_text(tmp_path) -> None:
    ranged = Campaign.from_toml(write(tmp_path, FAULTS.replace('seed = 3', 'seed = "5-6"'), 'ranged.toml'))
    assert ranged.grids[0]['seed'] == (5, 6) and {p.seed for p in ranged.points()} == {5, 6}
    mixed = FAULTS.replace('seed = 3', 'seed = "0,10-11"') + 'map = ["forest"]\nmap_seed = "7-8"\n'
    grid = Campaign.from_toml(write(tmp_path, mixed, 'mixed.toml')).grids[0]
    assert (grid['seed'], grid['map_seed']) == ((0, 10, 11), (7, 8))
    assert Campaign.from_toml(write(tmp_path, FAULTS, 'counted.toml')).grids[0]['seed'] == (0, 1, 2)


@pytest.mark.parametrize('case', list(BAD_CAMPAIGNS))
def test_a_bad_campaign_is_refused_before_any_run(tmp_path, capsys, fake_runs, case: str) -> None:
    text, message = BAD_CAMPAIGNS[case]
    path = write(tmp_path, text)
    assert main(['campaign', 'run', str(path), '--out', str(tmp_path / 'out'), '--workers', '1']) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith('error: ') and len(captured.err.splitlines()) == 1
    assert message in captured.err and captured.out == ''
    assert fake_runs[0] == [] and not (tmp_path / 'out' / RUNS_FILE).exists()


def test_a_campaign_file_named_from_another_directory_is_the_same_campaign(tmp_path, monkeypatch) -> None:
    """Issue 49: the same campaign file and folder named from another working directory were refused as "another
    campaign": its scene files were recorded relative to the working directory. They are recorded as the campaign
    file names them (relative to it): the same points, keys and record from anywhere, and the folder read back."""
    from vtube_planning.studies.campaign_store import prepare_folder, read_results

    study = tmp_path / 'study'
    (study / 'scenes').mkdir(parents=True)
    (study / 'scenes' / 'mine.toml').write_text(resources.files('vtube_planning.scenes').joinpath('C.toml').read_text())
    write(study, '[axes]\nscene = ["scenes/mine.toml", "C"]\nseed = 1\n', 'own.toml')
    out = tmp_path / 'results'
    seen = []
    for cwd, named in ((tmp_path, Path('study/own.toml')), (study / 'scenes', Path('../own.toml'))):
        monkeypatch.chdir(cwd)
        campaign = Campaign.from_toml(named)
        keys = [run_key(p, campaign.settings) for p in campaign.points()]
        assert prepare_folder(campaign, Path(os.path.relpath(out)), {key: {} for key in keys}) == {}  # not refused
        seen.append((campaign.points(), keys, campaign.to_json()))
    assert seen[0] == seen[1] and seen[0][0][0].scene == 'scenes/mine.toml'
    monkeypatch.chdir(tmp_path / 'study' / 'scenes')
    read, rows, missing = read_results(out)  # its scenes found from the recorded folder, from anywhere
    assert read.points() == seen[0][0] and (rows, missing) == ([], 2)
    assert json.loads((out / 'campaign.json').read_text())['scene_folder'] == str(study.resolve())
