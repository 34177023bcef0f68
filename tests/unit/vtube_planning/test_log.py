"""The one trajectory log: written atomically, read in the current schema, older versions upgraded, others named."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.errors import LogError
from vtube_planning.log import LOG_VERSION, LogWriter, read_log
from vtube_planning.npzfile import write_npz


def test_rows_round_trip_and_flush_periodically(tmp_path) -> None:
    log = LogWriter(tmp_path / 'run.npz', {'kind': 'test'}, flush_every=2)
    rng = np.random.default_rng(0)
    rows = [rng.standard_normal((2, 3)) for _ in range(5)]
    for k, positions in enumerate(rows):
        log.append(t_s=0.1 * k, positions_m=positions)
        positions[:] = 0.0  # the writer copied the row: the caller may reuse its buffer
    arrays, meta = read_log(tmp_path / 'run.partial.npz')  # unfinished: under the partial name
    assert arrays['positions_m'].shape == (4, 2, 3)  # the fifth row is not flushed yet
    assert meta['version'] == LOG_VERSION and meta['kind'] == 'test' and not (tmp_path / 'run.npz').exists()
    log.flush(finished=True)
    assert not (tmp_path / 'run.partial.npz').exists()
    arrays, meta = read_log(tmp_path / 'run.npz')
    np.testing.assert_allclose(arrays['t_s'], 0.1 * np.arange(5))
    assert meta['finished'] and np.all(arrays['positions_m'] == log.arrays()['positions_m'])


def test_an_interrupted_run_never_replaces_a_finished_log(tmp_path) -> None:
    first = LogWriter(tmp_path / 'run.npz', {'kind': 'test'})
    first.append(t_s=0.0, positions_m=np.ones((2, 2)))
    first.flush(finished=True)
    finished = (tmp_path / 'run.npz').read_bytes()
    second = LogWriter(tmp_path / 'run.npz', {'kind': 'test'}, flush_every=1)
    for k in range(3):  # a second run at the same path, interrupted after three rows
        second.append(t_s=float(k), positions_m=np.zeros((2, 2)))
    assert (tmp_path / 'run.npz').read_bytes() == finished
    arrays, meta = read_log(tmp_path / 'run.partial.npz')
    assert arrays['t_s'].tolist() == [0.0, 1.0, 2.0] and 'finished' not in meta


def test_a_memory_log_writes_nothing(tmp_path) -> None:
    log = LogWriter(None, {'kind': 'test'}, flush_every=1)
    log.append(t_s=0.0, positions_m=np.zeros((2, 1)))
    assert log.flush() is None and log.arrays()['positions_m'].shape == (1, 2, 1)
    assert not list(tmp_path.iterdir())


def test_rows_without_time_or_positions_are_refused(tmp_path) -> None:
    with pytest.raises(LogError, match=r"needs \['t_s', 'positions_m'\] .* lacks \['positions_m'\]"):
        LogWriter(tmp_path / 'x.npz', {}).append(t_s=0.0, poses=np.zeros((3, 2)))


def test_version_1_logs_are_upgraded(tmp_path) -> None:
    poses = np.random.default_rng(1).standard_normal((7, 3, 4))
    write_npz(tmp_path / 'old.npz', {'t_s': np.arange(7.0), 'poses': poses}, {'format': 'vtube-trajectory-1'})
    arrays, meta = read_log(tmp_path / 'old.npz')
    np.testing.assert_array_equal(arrays['positions_m'], poses[:, :2])
    np.testing.assert_array_equal(arrays['headings_rad'], poses[:, 2])
    assert meta['version'] == 1 and 'poses' not in arrays


def test_unknown_versions_and_formats_are_named(tmp_path) -> None:
    base = {'t_s': np.zeros(1), 'positions_m': np.zeros((1, 2, 1))}
    write_npz(tmp_path / 'new.npz', base, {'format': 'vtube-trajectory', 'version': 9})
    with pytest.raises(LogError, match='version 9; this vtube reads versions 1 to 2'):
        read_log(tmp_path / 'new.npz')
    write_npz(tmp_path / 'other.npz', base, {'format': 'something else'})
    with pytest.raises(LogError, match="not a vtube trajectory log \\(format 'something else'"):
        read_log(tmp_path / 'other.npz')
