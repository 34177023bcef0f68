"""``vtube robotarium sweep`` end to end on one tiny case: two robots through a short tube, one seed of V2's
initialization on the bundled simulator, built, flown, measured and judged; the rerun does nothing."""

from __future__ import annotations

import csv
from pathlib import Path

from vtube.cli.app import main

SHORT_TUBE = """
title = "A short straight tube"
description = "1.4 m from x = -1.0, 0.6 m wide (no narrowing: the density error in the dip is tested by unit)."

[tube.center]
start_xy_m = [-1.0, 0.0]
pieces = [{ kind = "line", length_m = 1.4 }]

[tube.width]
start_m = 0.3
parts = [{ kind = "constant" }]

[robotarium]
n_robots = 6
"""


def test_two_robots_through_a_short_tube_passes_and_a_rerun_skips_it(tmp_path: Path, capsys, monkeypatch) -> None:
    scene = tmp_path / 'short.toml'
    scene.write_text(SHORT_TUBE, encoding='utf-8')
    monkeypatch.chdir(tmp_path)  # the output named relatively, as the README's command does
    out = tmp_path / 'sweep'
    command = ['robotarium', 'sweep', 'short.toml', '--n', '2', '--seeds', '1', '--out', 'sweep']
    assert main(command) == 0, capsys.readouterr()
    with (out / 'runs.csv').open(newline='', encoding='utf-8') as handle:
        (row,) = csv.DictReader(handle)
    assert (row['scene'], row['n_robots'], row['status'], row['error']) == ('short', '2', 'PASS', '')
    assert (row['through'], row['parked'], row['body_on_wall'], row['too_close'], row['outside']) == (
        'True',
        'True',
        '0',
        '0',
        '0',
    )
    assert float(row['passing_time_s']) > 1.4 / 0.12  # no faster than v_max over the tube
    assert row['dip_error'] == ''  # no narrowing, no dip
    assert (out / 'files' / 'short_n2.py').is_file()
    assert '| short | PASS |' in (out / 'sweep.md').read_text(encoding='utf-8')
    capsys.readouterr()
    assert main(command) == 0
    assert '1 cases, 1 already done, 0 run now' in capsys.readouterr().out
