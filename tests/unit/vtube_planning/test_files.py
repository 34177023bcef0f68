"""Result files are written whole or not at all, and never through a link planted at their name."""

from __future__ import annotations

import os
import stat

import numpy as np
import pytest

from vtube_planning.files import write_atomically
from vtube_planning.npzfile import read_npz, write_npz


def test_text_bytes_and_writers_land_whole_in_a_new_folder(tmp_path) -> None:
    assert write_atomically(tmp_path / 'a' / 'x.txt', 'é\n').read_bytes() == 'é\n'.encode()
    assert write_atomically(tmp_path / 'y.bin', b'\x00\x01').read_bytes() == b'\x00\x01'
    assert write_atomically(tmp_path / 'z.bin', lambda handle: handle.write(b'abc')).read_bytes() == b'abc'
    mode = stat.S_IMODE((tmp_path / 'y.bin').stat().st_mode)
    mask = os.umask(0)
    os.umask(mask)
    assert mode == 0o666 & ~mask  # as an ordinary new file, not mkstemp's 0600
    assert sorted(p.name for p in tmp_path.iterdir()) == ['a', 'y.bin', 'z.bin']  # no temporary file left


def test_a_link_at_the_name_is_replaced_not_followed(tmp_path) -> None:
    target = tmp_path / 'precious.txt'
    target.write_text('keep me')
    link = tmp_path / 'report.md'
    link.symlink_to(target)
    write_atomically(link, 'the report')
    assert target.read_text() == 'keep me' and not link.is_symlink() and link.read_text() == 'the report'


def test_a_write_that_fails_leaves_the_old_file_and_no_temporary_one(tmp_path) -> None:
    path = write_atomically(tmp_path / 'metrics.json', '{"old": 1}')

    def half_then_fail(handle) -> None:
        handle.write(b'{"new": ')
        raise OSError(28, 'No space left on device')

    with pytest.raises(OSError, match='No space left'):
        write_atomically(path, half_then_fail)
    assert path.read_text() == '{"old": 1}' and [p.name for p in tmp_path.iterdir()] == ['metrics.json']


def test_a_log_ignores_a_link_planted_at_the_old_temporary_name(tmp_path) -> None:
    target = tmp_path / 'precious.txt'
    target.write_text('keep me')
    (tmp_path / 'run.npz.tmp').symlink_to(target)  # the name the log once wrote through
    write_npz(tmp_path / 'run.npz', {'x': np.arange(3.0)}, {'finished': True})
    arrays, meta = read_npz(tmp_path / 'run.npz', ValueError, 'log')
    assert target.read_text() == 'keep me' and arrays['x'].tolist() == [0.0, 1.0, 2.0] and meta == {'finished': True}


def test_a_full_disk_is_named_with_the_file(tmp_path) -> None:
    """Issue 49: a full disk said "[Errno 27] File too large" without naming the file."""
    import errno

    target = tmp_path / 'metrics.json'
    target.write_text('earlier')

    def too_large(handle) -> None:
        handle.write(b'part')
        raise OSError(errno.EFBIG, 'File too large')

    with pytest.raises(
        OSError, match=rf'File too large while writing {target}; the file there was left as it was'
    ) as err:
        write_atomically(target, too_large)
    assert err.value.errno == errno.EFBIG and target.read_text() == 'earlier'
    assert [p.name for p in tmp_path.iterdir()] == ['metrics.json']
