"""``vtube export``: a log written as a bag and as CSV, read back; what cannot be written refused."""

from __future__ import annotations

import numpy as np

from robotarium_exp.analysis.loaders import load_trajectory
from vtube.cli import main
from vtube.cli.export import COMMAND
from vtube_planning.log import LOG_FORMAT, LOG_VERSION
from vtube_planning.npzfile import write_npz


def test_a_log_exported_as_a_bag_and_as_csv(tmp_path, capsys) -> None:
    t = 0.02 * np.arange(50)
    positions = np.stack([np.stack([t, t + k], axis=1) for k in range(3)], axis=2)  # (50, 2, 3)
    log = tmp_path / 'log.npz'
    write_npz(log, {'t_s': t, 'positions_m': positions}, {'format': LOG_FORMAT, 'version': LOG_VERSION, 'kind': 't'})
    assert main(['export', str(log), '--format', 'mcap', '--out', str(tmp_path / 'bag'), '--scene', 'A']) == 0
    assert capsys.readouterr().out.splitlines()[-1] == f'written {tmp_path / "bag"} (mcap): 3 robots, 50 frames'
    np.testing.assert_array_equal(load_trajectory([tmp_path / 'bag']).positions_m, positions)
    assert main(['export', str(log), '--format', 'csv', '--out', str(tmp_path / 'run.csv')]) == 0
    assert len((tmp_path / 'run.csv').read_text().splitlines()) == 1 + 50 * 3
    assert main(['export', str(log), '--format', 'mcap', '--out', str(tmp_path / 'bag')]) == 2  # it exists
    assert 'exists; a bag is a new folder' in capsys.readouterr().err and COMMAND.words == 'export'
