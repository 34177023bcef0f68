"""Provenance records: version, command line, time, scene and plan hashes; the scene copied beside results."""

from __future__ import annotations

import hashlib
import json
import sys
from datetime import datetime, timezone

from vtube_planning import __version__
from vtube_planning.geometry.scene import load_scene
from vtube_planning.provenance import command_line, copy_scene, provenance, sha256_of


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
