"""The ablation grid end to end from the command line: its table, report and figures, resumed with nothing to run."""

from __future__ import annotations

import pytest

from vtube.cli import main
from vtube_planning.studies.campaign_store import read_results
from vtube_planning.studies.study import ABLATIONS, Point, run_point


def test_a_reduced_grid_end_to_end(tmp_path, capsys) -> None:
    out = tmp_path / 'grid'
    argv = ['ablation', '--out', str(out), '--scenes', 'C', '--sizes', '20', '--seeds', '2', '--models', 'paper']
    argv += ['--saturations', 'radial,forward']
    assert main([*argv, '--workers', '2']) == 0  # both cores
    _, rows, missing = read_results(out)
    assert len(rows) == 2 * 2 * len(ABLATIONS) and missing == 0
    assert {r['mode'] for r in rows} == set(ABLATIONS) and {r['seed'] for r in rows} == {0, 1}
    forward = [r for r in rows if r['saturation'] == 'forward']
    assert len(forward) == len(rows) // 2 and all(r['reversing_share'] == 0.0 for r in forward)
    radial_unplanned = [r for r in rows if r['saturation'] == 'radial' and r['mode'] == 'no planning']
    assert all(r['reversing_share'] > 0.0 for r in radial_unplanned)  # the paper's sat reverses robots here
    for row in rows[::5]:  # the table holds what one run measures, typed back
        fields = ('scene', 'mode', 'n_robots', 'seed', 'model', 'saturation')
        fresh = run_point(Point(**{f: row[f] for f in fields}))
        for key, value in fresh.items():
            assert row[key] == (pytest.approx(value, nan_ok=True) if isinstance(value, float) else value)
    text = (out / 'report.md').read_text()
    assert text.startswith("Campaign 'ablation': 24 runs.")
    assert '| paper model, radial sat | T +' in text  # 1 cell per setting: T +k =m -n with k+m+n = 1
    assert '### Scene C, N = 20, paper model, radial sat (seeds 0-1)' in text
    assert '### Scene C, N = 20, paper model, forward sat (seeds 0-1)' in text
    assert '- 24 runs made by `vtube ablation --out' in text and 'T +0 =0 -0 ?1' in text  # two seeds: no verdict
    assert "| planning - no planning (the paper's comparison) |" in text
    for figure in ('differences.png', 'verdicts.png', 'means.png'):
        assert (out / figure).read_bytes()[:4] == b'\x89PNG'
    assert 'ablation: 24 runs, 0 already done, 24 run now on 2 local processes in' in capsys.readouterr().out
    (out / 'report.md').unlink()
    assert main(['campaign', 'report', str(out)]) == 0  # the report again, from the folder alone
    assert (out / 'report.md').read_text() == text
    assert main([*argv, '--workers', '1']) == 0  # the same command again: nothing left to run
    assert '24 already done, 0 run now' in capsys.readouterr().out
    assert main(['campaign', 'verify', str(out), '--runs', '2', '--workers', '1']) == 0  # this code made it
    assert 'the folder holds what this code produces' in capsys.readouterr().out
