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


def test_a_run_of_an_own_scene_finds_the_scene_copy_beside_its_log(tmp_path, capsys) -> None:
    """Issue 49: `vtube replay LOG` of an own scene needed --scene although `simulate` had copied the scene file
    beside the log (``scene_<name>.toml``)."""
    from pathlib import Path

    t = 0.02 * np.arange(50)
    positions = np.stack([np.stack([3.0 * t + k, 0.0 * t + k], axis=1) for k in range(2)], axis=2)
    meta = {'format': LOG_FORMAT, 'version': LOG_VERSION, 'kind': 'simulation', 'scene': 'my_tube', 'planned': False}
    log = tmp_path / 'log.npz'
    write_npz(log, {'t_s': t, 'positions_m': positions}, meta)
    shipped = Path(__file__).resolve().parents[4] / 'vtube_planning' / 'scenes' / 'A.toml'
    (tmp_path / 'scene_my_tube.toml').write_text(shipped.read_text(encoding='utf-8'), encoding='utf-8')
    assert main(['replay', str(log), '--out', str(tmp_path / 'run.html')]) == 0
    assert capsys.readouterr().out.splitlines()[-1].endswith('2 robots, 0.98 s, 30 of 50 frames')
    (tmp_path / 'scene_my_tube.toml').unlink()
    assert main(['replay', str(log), '--out', str(tmp_path / 'run.html')]) == 2
    assert 'no copy scene_my_tube.toml lies beside it; give its file: --scene' in capsys.readouterr().err
