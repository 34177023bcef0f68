"""The study's ablation grid: each mode switches exactly the part it names; the grid runs end to end."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from vtube.cli import main
from vtube_planning import load_scene
from vtube_planning.campaign_store import read_results
from vtube_planning.study import ABLATIONS, Point, ablation_setup, run_point
from vtube_planning.swarm.simulate import SimConfig, default_constant_speed, simulate


@pytest.fixture(scope='module')
def setups():
    scene = load_scene('C')
    return scene, {mode: ablation_setup(mode, scene, scene.swarm, 0.02) for mode in ABLATIONS}


def test_each_mode_switches_exactly_the_part_it_names(setups) -> None:
    scene, s = setups
    full = s['planning']
    assert full.plan is not None and full.control == scene.control and full.constant_speed_mps is None
    # without (p7): planned again with (p7) left out, nothing else changed; the dip before the narrowing is gone
    no_p7 = s['planning without (p7)']
    assert no_p7.plan is not None and no_p7.control == full.control
    assert no_p7.plan.options == replace(full.plan.options, predictive_model='none')
    assert full.plan.active['p7'].any() and not no_p7.plan.active['p7'].any()
    assert no_p7.plan.density_per_m2.min() > full.plan.density_per_m2.min() + 0.05
    # (a3) off: the same plan, only the gain of (a3) and its feed-forward zeroed
    off = s['planned speed, (a3) off']
    assert off.plan is full.plan
    assert off.control.k_ra_m3ps == 0.0 and not off.control.feedforward
    assert replace(off.control, k_ra_m3ps=full.control.k_ra_m3ps, feedforward=full.control.feedforward) == full.control
    # flat: the full plan's grid at the constant mid speed and the density rho_d; (a3) as in the full plan
    flat = s['constant speed, (a3) to rho_d']
    assert flat.plan is not None and flat.control == full.control
    np.testing.assert_array_equal(flat.plan.l_m, full.plan.l_m)
    assert np.all(flat.plan.speed_mps == default_constant_speed(scene.swarm))
    assert np.all(flat.plan.density_per_m2 == scene.swarm.rho_d_per_m2)
    # no planning: no plan; the two differ in their constant speed only
    mid, fast = s['no planning'], s['no planning at v_max']
    assert mid.plan is None and fast.plan is None and mid.control == fast.control
    assert (mid.constant_speed_mps, fast.constant_speed_mps) == (3.5, scene.swarm.v_max_mps)


def test_a3_off_keeps_every_avoidance_radius_and_a3_on_changes_them(setups) -> None:
    scene, s = setups
    config = SimConfig(time_limit_s=8.0)
    radii = {}
    for mode in ('planning', 'planned speed, (a3) off'):
        setup = s[mode]
        result = simulate(scene.tube, scene.swarm, setup.control, plan=setup.plan, config=config)
        radii[mode] = result.r_a_m
    assert np.all(radii['planned speed, (a3) off'] == scene.swarm.r_a_m)
    assert radii['planning'].max() > 1.2 * scene.swarm.r_a_m


@pytest.mark.slow
def test_a_reduced_grid_end_to_end(tmp_path, capsys) -> None:
    out = tmp_path / 'grid'
    argv = ['ablation', '--out', str(out), '--scenes', 'C', '--sizes', '20', '--seeds', '2', '--models', 'paper']
    argv += ['--saturations', 'radial,forward']
    assert main([*argv, '--workers', '1']) == 0
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
    assert '### Scene C, N = 20, paper model, radial sat (2 seeds)' in text
    assert '### Scene C, N = 20, paper model, forward sat (2 seeds)' in text
    assert "| planning - no planning (the paper's comparison) |" in text
    for figure in ('differences.png', 'means.png'):
        assert (out / figure).read_bytes()[:4] == b'\x89PNG'
    assert 'ablation: 24 runs, 0 already done, 24 run now on 1 local process in' in capsys.readouterr().out
    (out / 'report.md').unlink()
    assert main(['campaign', 'report', str(out)]) == 0  # the report again, from the folder alone
    assert (out / 'report.md').read_text() == text
    assert main([*argv, '--workers', '1']) == 0  # the same command again: nothing left to run
    assert '24 already done, 0 run now' in capsys.readouterr().out


def test_bad_grid_arguments(tmp_path, capsys) -> None:
    assert main(['ablation', '--out', str(tmp_path), '--sizes', '20,x']) == 2
    assert '--sizes must be comma-separated whole numbers >= 1' in capsys.readouterr().err
    assert main(['ablation', '--out', str(tmp_path), '--models', 'paper,fast']) == 2
    assert "axes.model holds 'fast'; choose from 'paper', 'acceleration limits'." in capsys.readouterr().err
    assert main(['ablation', '--out', str(tmp_path), '--saturations', 'clip']) == 2
    assert "axes.saturation holds 'clip'; choose from 'radial', 'forward'." in capsys.readouterr().err


def test_the_verdict_summary_counts_cells_on_synthetic_rows() -> None:
    """Two cells: in N = 20 planning is 0.1 m safer and 1 s faster on every seed; in N = 40 nothing differs."""
    from vtube_planning.study_report import paired_table, verdict_summary

    rng = np.random.default_rng(0)
    rows = []
    for n, gain in ((20, 1.0), (40, 0.0)):
        for seed in range(10):
            base = {'scene': 'C', 'n_robots': n, 'seed': seed, 'model': 'paper', 'saturation': 'radial'}
            spread = rng.normal(0.0, 0.02)
            rows.append(base | {'mode': 'no planning', 'passing_time_s': 20.0, 'min_distance_m': 0.8 + spread})
            rows.append(
                base
                | {
                    'mode': 'planning',
                    'passing_time_s': 20.0 - gain + rng.normal(0.0, 0.01) * gain,
                    'min_distance_m': 0.8 + spread + 0.1 * gain + rng.normal(0.0, 0.005) * gain,
                }
            )
    verdicts = {(p['n_robots'], p['metric']): p['verdict'] for p in paired_table(rows)}
    assert verdicts == {
        (20, 'passing_time_s'): 'holds',
        (20, 'min_distance_m'): 'holds',
        (40, 'passing_time_s'): 'does not hold',
        (40, 'min_distance_m'): 'does not hold',
    }
    text = verdict_summary(rows)
    assert "| setting | planning - no planning (the paper's comparison) |" in text  # the only comparison flown
    assert '| paper model, radial sat | T +1 =1 -0, D +1 =1 -0 |' in text
