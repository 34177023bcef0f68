"""The package's file format: arrays and JSON metadata, written atomically, read without pickle, errors named."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.errors import LogError, PlanError
from vtube_planning.npzfile import META_KEY, read_npz, write_npz


def test_arrays_and_metadata_round_trip(tmp_path) -> None:
    arrays = {'x': np.arange(6.0).reshape(2, 3), 'flags': np.array([True, False]), 'n': np.array(3)}
    meta = {'name': 'é', 'nested': {'values': [1, 2.5, None]}}
    path = write_npz(tmp_path / 'deep' / 'file.npz', arrays, meta)
    assert path == tmp_path / 'deep' / 'file.npz' and not list(path.parent.glob('*.tmp'))
    got, got_meta = read_npz(path, PlanError, 'plan')
    assert got_meta == meta and set(got) == set(arrays)
    for key, value in arrays.items():
        np.testing.assert_array_equal(got[key], value)
        assert got[key].dtype == value.dtype


def test_writing_again_replaces_the_file_whole(tmp_path) -> None:
    path = tmp_path / 'f.npz'
    write_npz(path, {'a': np.zeros(1000)}, {'v': 1})
    write_npz(path, {'b': np.ones(2)}, {'v': 2})
    arrays, meta = read_npz(path, PlanError, 'plan')
    assert meta == {'v': 2} and set(arrays) == {'b'}


def test_object_arrays_are_never_unpickled(tmp_path) -> None:
    path = tmp_path / 'evil.npz'
    np.savez(path, **{META_KEY: np.array('{}')}, obj=np.array([{'a': 1}], dtype=object))
    with pytest.raises(LogError, match=r"cannot read log .*evil.npz'.*give a log as vtube writes it") as raised:
        read_npz(path, LogError, 'log')
    assert 'holds pickled objects, which are never loaded' in str(raised.value)
    assert 'allow_pickle' not in str(raised.value)  # numpy's advice to load them is not passed on


def saving(save, *args, **kwargs):
    """A writer of ``save(file, ...)`` into a path, the file closed after."""

    def make(path):
        with path.open('wb') as fh:
            save(fh, *args, **kwargs)

    return make


@pytest.mark.parametrize(
    ('make', 'match'),
    [
        (lambda p: p.write_bytes(b'not a zip'), r'it is not an .npz archive, or it is damaged'),
        (saving(np.save, np.zeros(3)), r'holds one bare array \(.npy\), not a plan'),
        (saving(np.savez, a=np.zeros(2)), r'is an .npz archive without vtube metadata, not a plan'),
        (saving(np.savez, **{META_KEY: np.array('{oops')}), r'its metadata is damaged'),
        (lambda p: None, r'cannot read plan .*missing.npz'),
    ],
    ids=['not-zip', 'bare-npy', 'no-meta', 'bad-json', 'missing'],
)
def test_unreadable_files_raise_the_given_error_naming_the_problem(tmp_path, make, match: str) -> None:
    path = tmp_path / 'missing.npz'
    make(path)
    with pytest.raises(PlanError, match=match):
        read_npz(path, PlanError, 'plan')
