"""Provenance records: version, command line, time, scene and plan hashes; the scene copied beside results."""

from __future__ import annotations

import hashlib
import json
import sys
from datetime import datetime, timezone

from vtube_planning import __version__
from vtube_planning.geometry.scene import load_scene
from vtube_planning.provenance import command_line, copy_scene, made_counts, provenance, sha256_of


def test_sha256_of_text_is_that_of_its_utf8_bytes() -> None:
    assert sha256_of(b'abc') == hashlib.sha256(b'abc').hexdigest()
    assert sha256_of('é') == hashlib.sha256('é'.encode()).hexdigest()


def test_the_bare_record_has_version_command_and_utc_time(monkeypatch) -> None:
    monkeypatch.setattr(sys, 'argv', ['vtube', 'plan', 'my scene.toml'])
    before = datetime.now(timezone.utc).replace(microsecond=0)
    record = provenance()
    assert set(record) == {'vtube_version', 'command', 'utc'}
    assert record['vtube_version'] == __version__
    assert record['command'] == "vtube plan 'my scene.toml'"  # quoted as a shell would need it
    assert before <= datetime.fromisoformat(record['utc']) <= datetime.now(timezone.utc)
    json.dumps(record)


def test_the_command_line_given_is_recorded_inside_only() -> None:
    with command_line(['simulate', 'A', '--seed', '3']):
        assert provenance()['command'] == 'simulate A --seed 3'
        with command_line(['inner']):
            assert provenance()['command'] == 'inner'
        assert provenance()['command'] == 'simulate A --seed 3'
    assert provenance()['command'] != 'simulate A --seed 3'


def test_scene_plan_and_seeds_are_recorded_by_hash(tmp_path) -> None:
    scene = load_scene('B')
    plan_file = tmp_path / 'plan.npz'
    plan_file.write_bytes(b'\x00plan bytes')
    record = provenance(scene=scene, plan_file=plan_file, seeds=(4, 5))
    assert record['scene'] == 'B' and record['scene_source'] == scene.source
    assert record['scene_sha256'] == hashlib.sha256(scene.text.encode()).hexdigest()
    assert record['plan_sha256'] == hashlib.sha256(b'\x00plan bytes').hexdigest()
    assert record['seeds'] == [4, 5]


def test_the_scene_copy_has_the_bytes_it_was_read_from(tmp_path) -> None:
    scene = load_scene('A')
    path = copy_scene(scene, tmp_path / 'new' / 'folder')
    assert path == tmp_path / 'new' / 'folder' / 'scene_A.toml'
    assert path.read_text(encoding='utf-8') == scene.text
    assert load_scene(path).tube.fingerprint() == scene.tube.fingerprint()


def test_the_source_commit_of_a_checkout_and_of_a_copy(tmp_path, monkeypatch) -> None:
    """A git checkout gives its HEAD, '-dirty' when its code (not its results) differs; a copy gives None."""
    import subprocess

    from vtube_planning import provenance as module

    def git(*words: str) -> str:
        return subprocess.run(['git', '-C', str(tmp_path), *words], capture_output=True, text=True, check=True).stdout

    (tmp_path / 'vtube_planning').mkdir()
    (tmp_path / 'docs').mkdir()
    for name in ('vtube_planning/provenance.py', 'docs/report.md'):
        (tmp_path / name).write_text('x\n', encoding='utf-8')
    monkeypatch.setattr(module, '__file__', str(tmp_path / 'vtube_planning' / 'provenance.py'))
    assert module.source_commit() is None  # not a checkout
    git('init', '-q')
    git('add', '.')
    git('-c', 'user.name=t', '-c', 'user.email=t@t', 'commit', '-qm', 'c')
    head = git('rev-parse', 'HEAD').strip()
    assert module.source_commit() == head
    (tmp_path / 'docs' / 'report.md').write_text('new results\n', encoding='utf-8')
    assert module.source_commit() == head  # results rewritten: the code is still that commit's
    (tmp_path / 'vtube_planning' / 'provenance.py').write_text('y\n', encoding='utf-8')
    assert module.source_commit() == head + '-dirty'


def test_each_session_is_credited_with_the_runs_it_made_not_those_it_was_to_make() -> None:
    # three sessions of a 10-run campaign: the first stopped after 4 runs, the second at once, the third made 5
    # (one run still missing); each entry records the runs done before it and those it was to make
    made = [{'done_before': 0, 'to_run': 10}, {'done_before': 4, 'to_run': 6}, {'done_before': 4, 'to_run': 6}]
    assert made_counts(made, 9) == ['4', '0', '5']
    assert made_counts([{'to_run': 7}], 7) == ['7']  # a folder from before the runs done were recorded
