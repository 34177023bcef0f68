"""``vtube replay``: a log written as a page, with the scene its log records or the one given; a run without a plan
shows none."""

from __future__ import annotations

import numpy as np

from vtube.cli import main
from vtube.cli.replay import COMMAND
from vtube_planning.log import LOG_FORMAT, LOG_VERSION
from vtube_planning.npzfile import write_npz


def test_a_log_replayed_as_a_page(tmp_path, capsys) -> None:
    t = 0.02 * np.arange(100)
    positions = np.stack([np.stack([3.0 * t + k, 0.0 * t + k], axis=1) for k in range(3)], axis=2)  # (100, 2, 3)
    meta = {'format': LOG_FORMAT, 'version': LOG_VERSION, 'kind': 'simulation', 'scene': 'A', 'planned': False}
    log = tmp_path / 'log.npz'
    write_npz(log, {'t_s': t, 'positions_m': positions}, meta)
    page = tmp_path / 'pages' / 'run.html'
    assert main(['replay', str(log), '--out', str(page)]) == 0
    line = capsys.readouterr().out.splitlines()[-1]
    assert line.startswith(f'written {page} (') and line.endswith('3 robots, 1.98 s, 60 of 100 frames')
    text = page.read_text(encoding='utf-8')
    assert '"planned":null' in text and 'no plan is shown: the run flew none' in text
    assert main(['replay', str(log), '--out', str(page), '--scene', 'A', '--plan', str(tmp_path / 'none.npz')]) == 2
    assert COMMAND.words == 'replay'
    write_npz(log, {'t_s': t, 'positions_m': positions}, meta | {'scene': 'my_tube'})
    assert main(['replay', str(log), '--out', str(page)]) == 2
    assert "records scene 'my_tube', which is not shipped" in capsys.readouterr().err
