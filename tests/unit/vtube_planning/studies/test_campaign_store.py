"""A campaign's folder: prepared before any run, rows kept only when whole and finished, read back typed."""

from __future__ import annotations

import csv
import hashlib
import json
import math

import pytest

from vtube_planning.studies.campaign import Campaign, CampaignError, run_key
from vtube_planning.studies.campaign_store import (
    CAMPAIGN_FILE,
    RUNS_FILE,
    prepare_folder,
    prepare_table,
    read_results,
    typed_row,
)

GRID = '[axes]\nscene = ["C"]\nmode = ["planning", "no planning"]\nseed = 2\n'


@pytest.fixture
def campaign(tmp_path) -> Campaign:
    path = tmp_path / 'grid.toml'
    path.write_text(GRID, encoding='utf-8')
    return Campaign.from_toml(path)


def finished_row(campaign: Campaign, k: int, **changes) -> dict[str, str]:
    point = campaign.points()[k]
    row = dict.fromkeys(campaign.columns, '')
    row |= {'key': run_key(point, campaign.settings), 'scene': point.scene, 'mode': point.mode}
    row |= {'n_robots': str(point.n_robots), 'seed': str(point.seed), 'model': point.model}
    row |= {'saturation': point.saturation, 'passing_time_s': '12.5', 'completed': 'True', 'version': '1.0'}
    return {c: v for c, v in (row | changes).items() if c in campaign.columns}


def write_rows(path, columns, rows, tail: str = '') -> None:
    with path.open('w', newline='', encoding='utf-8') as handle:
        writer = csv.DictWriter(handle, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)
        handle.write(tail)


def test_a_new_folder_gets_the_campaign_and_an_empty_table(tmp_path, campaign) -> None:
    out = tmp_path / 'new' / 'out'
    keys = {key: {} for key in (run_key(p, campaign.settings) for p in campaign.points())}
    assert prepare_folder(campaign, out, keys) == {}
    assert json.loads((out / CAMPAIGN_FILE).read_text()) == campaign.to_json()
    assert (out / RUNS_FILE).read_text().splitlines() == [','.join(campaign.columns)]
    assert read_results(out)[1:] == ([], 4)
    assert not list(out.glob('.*.partial'))


def test_only_whole_finished_rows_of_this_grid_are_kept(tmp_path, campaign) -> None:
    out = tmp_path / 'out'
    keys = [run_key(p, campaign.settings) for p in campaign.points()]
    prepare_folder(campaign, out, {key: {} for key in keys})
    rows = [
        finished_row(campaign, 0),
        finished_row(campaign, 1, error='ValueError: no'),  # failed: run again
        finished_row(campaign, 2, version=''),  # no version: not finished
        finished_row(campaign, 3, key='another grid'),
    ]
    write_rows(out / RUNS_FILE, campaign.columns, rows, tail=keys[3][:6] + ',C')  # and a line cut short
    done = prepare_folder(campaign, out, {key: {} for key in keys})
    assert list(done) == [keys[0]]
    with (out / RUNS_FILE).open(newline='', encoding='utf-8') as handle:
        assert [r['key'] for r in csv.DictReader(handle)] == [keys[0]]  # the table rewritten with it alone
    _, typed, missing = read_results(out)
    assert missing == 3 and typed[0]['passing_time_s'] == 12.5 and typed[0]['completed'] is True


def test_a_folder_of_another_campaign_or_other_columns_is_refused(tmp_path, campaign) -> None:
    out = tmp_path / 'out'
    prepare_folder(campaign, out, {})
    other = Campaign.from_dict(campaign.to_json() | {'name': 'other'})
    with pytest.raises(CampaignError, match='holds the results of another campaign'):
        prepare_folder(other, out, {})
    write_rows(out / RUNS_FILE, ['key', 'scene'], [])
    with pytest.raises(CampaignError, match='has other columns than this campaign'):
        prepare_folder(campaign, out, {})


def test_any_table_of_runs_keeps_its_done_rows_and_refuses_other_settings(tmp_path) -> None:
    out, columns = tmp_path / 'sweep', ['key', 'n', 'error', 'version']
    assert prepare_table(out, 'sweep.json', {'seeds': 3}, columns, {'a': {}, 'b': {}}, what='sweep') == {}
    assert json.loads((out / 'sweep.json').read_text(encoding='utf-8')) == {'seeds': 3}
    rows = [['a', '1', '', '0.1'], ['b', '2', 'ValueError: x', '0.1'], ['c', '3', '', '0.1']]
    write_rows(out / RUNS_FILE, columns, [dict(zip(columns, row, strict=True)) for row in rows])
    done = prepare_table(out, 'sweep.json', {'seeds': 3}, columns, {'a': {}, 'b': {}}, what='sweep')
    assert list(done) == ['a']  # b raised, c is not of this grid
    with pytest.raises(CampaignError, match='holds the results of another sweep'):
        prepare_table(out, 'sweep.json', {'seeds': 2}, columns, {'a': {}}, what='sweep')


def test_an_unwritable_place_and_a_folder_without_a_campaign_are_named(tmp_path, campaign) -> None:
    blocker = tmp_path / 'file'
    blocker.write_text('x')
    with pytest.raises(OSError, match='choose another --out before any run starts'):
        prepare_folder(campaign, blocker / 'out', {})
    with pytest.raises(CampaignError, match=r'holds no campaign \(campaign.json and runs.csv\); run `vtube campaign'):
        read_results(tmp_path)


def test_typed_rows_get_numbers_booleans_and_nan_back() -> None:
    row = {'seed': '3', 'passing_time_s': '', 'completed': 'False', 'wall_s': '1.5', 'scene': 'C', 'extra': 7}
    typed = typed_row(row, list(row))
    assert typed['seed'] == 3 and isinstance(typed['seed'], int)
    assert math.isnan(typed['passing_time_s']) and typed['completed'] is False
    assert typed['wall_s'] == 1.5 and typed['scene'] == 'C' and typed['extra'] == 7


def test_a_table_written_before_the_later_axes_is_read_and_resumed_with_their_defaults(tmp_path, campaign) -> None:
    """A committed table without the lag and compensation columns (written before they existed): its rows keep their
    keys, read back with the defaults, and a resumed run rewrites it with every column."""
    out = tmp_path / 'out'
    older = [c for c in campaign.columns if c not in ('lag_s', 'compensation', 'scene_sha256')]
    out.mkdir()
    (out / CAMPAIGN_FILE).write_text(json.dumps(campaign.to_json(), indent=1) + '\n', encoding='utf-8')
    rows = [{c: v for c, v in finished_row(campaign, k).items() if c in older} for k in range(2)]
    write_rows(out / RUNS_FILE, older, rows)
    _, rows, missing = read_results(out)
    assert missing == 2 and [(r['lag_s'], r['compensation']) for r in rows] == [(0.0, 'none')] * 2
    keys = {run_key(p, campaign.settings): {'version': '1.0', 'scene_sha256': 'abc'} for p in campaign.points()}
    done = prepare_folder(campaign, out, keys)  # a table from before: no hash recorded, accepted
    assert len(done) == 2 and all(row['compensation'] == 'none' for row in done.values())
    with (out / RUNS_FILE).open(newline='', encoding='utf-8') as handle:
        assert csv.DictReader(handle).fieldnames == campaign.columns
    other = [c for c in older if c != 'dropout']  # any other missing column still refuses the table
    write_rows(out / RUNS_FILE, other, [])
    with pytest.raises(CampaignError, match='has other columns than this campaign'):
        prepare_folder(campaign, out, keys)


def test_finished_runs_of_another_version_or_scene_text_are_refused_not_resumed(tmp_path, campaign) -> None:
    out = tmp_path / 'out'
    keys = [run_key(p, campaign.settings) for p in campaign.points()]
    now = {key: {'version': '1.0', 'scene_sha256': 'abc'} for key in keys}
    prepare_folder(campaign, out, now)
    write_rows(out / RUNS_FILE, campaign.columns, [finished_row(campaign, 0, scene_sha256='abc')])
    assert list(prepare_folder(campaign, out, now)) == [keys[0]]  # the same version and scene: resumed
    edited = {key: {'version': '1.0', 'scene_sha256': 'def'} for key in keys}
    with pytest.raises(CampaignError, match=r"made otherwise \(scene_sha256 'abc' where this run has 'def'\)"):
        prepare_folder(campaign, out, edited)
    newer = {key: {'version': '1.1', 'scene_sha256': 'abc'} for key in keys}
    with pytest.raises(CampaignError, match=r"version '1.0' where this run has '1.1'.*another --out"):
        prepare_folder(campaign, out, newer)
    assert len(read_results(out)[1]) == 1  # nothing lost on the way


def test_a_folder_is_held_by_one_run_and_a_dead_runs_lock_is_taken_over(tmp_path) -> None:
    import os

    from vtube_planning.studies.campaign_store import LOCK_FILE, holding

    out = tmp_path / 'out'
    with holding(out, 'campaign'):
        held = json.loads((out / LOCK_FILE).read_text())
        assert held['pid'] == os.getpid()
        refused = pytest.raises(CampaignError, match=rf'written by another campaign run \(process {os.getpid()} on')
        with refused, holding(out, 'campaign'):
            pass
    assert not (out / LOCK_FILE).exists()  # released
    dead = {'pid': 2**22 + 12345, 'host': held['host'], 'since': 'then'}  # beyond pid_max: no such process
    (out / LOCK_FILE).write_text(json.dumps(dead))
    with holding(out, 'campaign'):
        assert json.loads((out / LOCK_FILE).read_text())['pid'] == os.getpid()
    (out / LOCK_FILE).write_text(json.dumps(dead | {'host': 'elsewhere'}))  # another machine's: cannot tell
    with (
        pytest.raises(CampaignError, match='process 4206649 on elsewhere, since then.*delete'),
        holding(out, 'campaign'),
    ):
        pass


def test_a_value_edited_by_hand_is_named_not_a_traceback(tmp_path, campaign) -> None:
    out = tmp_path / 'out'
    keys = [run_key(p, campaign.settings) for p in campaign.points()]
    prepare_folder(campaign, out, {key: {} for key in keys})
    for column, value, words in (('passing_time_s', 'fast', 'a number'), ('completed', 'yes', 'True or False')):
        write_rows(out / RUNS_FILE, campaign.columns, [finished_row(campaign, 0, **{column: value})])
        with pytest.raises(CampaignError, match=rf"runs.csv, the run {keys[0]}: {column} = '{value}' is not {words}"):
            read_results(out)
    with pytest.raises(CampaignError, match="seed = 'abc' is not a whole number"):
        typed_row({'seed': 'abc'}, ['seed'])


def test_a_folder_recorded_before_item_16_is_resumed_and_rewritten(tmp_path, monkeypatch) -> None:
    """Issue 49, item 16's migration: a folder made before recorded its scene files relative to the working
    directory (the old `from_dict` took `str(base / name)`, base being the campaign file's folder as given, and
    `to_json` wrote that; its rows are keyed on it). Named from the working directory it was made in, it is the same
    campaign (not "another campaign"): its finished rows are kept, keyed again, and the folder is rewritten as today's
    code writes it, read back from anywhere. A record naming another file is still another campaign."""
    from dataclasses import asdict
    from importlib import resources
    from pathlib import Path

    from vtube_planning.studies.campaign_store import SCENE_FOLDER

    study = tmp_path / 'study'
    (study / 'scenes').mkdir(parents=True)
    text = resources.files('vtube_planning.scenes').joinpath('C.toml').read_text()
    (study / 'scenes' / 'mine.toml').write_text(text, encoding='utf-8')
    (study / 'own.toml').write_text('[axes]\nscene = ["scenes/mine.toml", "C"]\nseed = 1\n', encoding='utf-8')
    monkeypatch.chdir(tmp_path)
    old = Campaign.from_dict({'axes': {'scene': ['study/scenes/mine.toml', 'C'], 'seed': 1}})  # as the old code had it
    out = tmp_path / 'results'
    out.mkdir()
    (out / CAMPAIGN_FILE).write_text(json.dumps(old.to_json(), indent=1) + '\n', encoding='utf-8')
    mine = old.points()[0]
    assert mine.scene == 'study/scenes/mine.toml'
    row = dict.fromkeys(old.columns, '') | {'key': run_key(mine, old.settings), 'passing_time_s': '12.5'}
    row |= {axis: str(value) for axis, value in asdict(mine).items()}  # every axis, as csv writes it
    sha = hashlib.sha256(text.encode()).hexdigest()
    write_rows(out / RUNS_FILE, old.columns, [row | {'version': '1.0', 'scene_sha256': sha, 'completed': 'True'}])

    campaign = Campaign.from_toml(Path('study/own.toml'))
    points = campaign.points()
    expected = {run_key(p, campaign.settings): {'version': '1.0', 'scene_sha256': sha} for p in points}
    done = prepare_folder(campaign, out, expected)
    new_key = run_key(points[0], campaign.settings)
    assert points[0].scene == 'scenes/mine.toml' and new_key != row['key']
    assert list(done) == [new_key] and done[new_key]['scene'] == 'scenes/mine.toml'
    assert done[new_key]['passing_time_s'] == '12.5'
    recorded = json.loads((out / CAMPAIGN_FILE).read_text())
    assert recorded['grids'][0]['scene'] == ['scenes/mine.toml', 'C'] and recorded[SCENE_FOLDER] == str(study.resolve())
    monkeypatch.chdir(study / 'scenes')  # today's form: the same from anywhere
    read, rows, missing = read_results(out)
    assert [r['key'] for r in rows] == [new_key] and missing == 1 and read.points() == points

    monkeypatch.chdir(tmp_path)
    (tmp_path / 'elsewhere').mkdir()
    (tmp_path / 'elsewhere' / 'mine.toml').write_text(text, encoding='utf-8')  # the same text, another file
    other = tmp_path / 'other'
    other.mkdir()
    elsewhere = Campaign.from_dict({'axes': {'scene': ['elsewhere/mine.toml', 'C'], 'seed': 1}})
    (other / CAMPAIGN_FILE).write_text(json.dumps(elsewhere.to_json()), encoding='utf-8')
    with pytest.raises(CampaignError, match='holds the results of another campaign'):
        prepare_folder(campaign, other, expected)
    assert json.loads((other / CAMPAIGN_FILE).read_text()) == elsewhere.to_json()  # left as it was
