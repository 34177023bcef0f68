"""The ablation modes: each switches exactly the part it names; the grid command refuses bad arguments."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from vtube.cli import main
from vtube_planning.errors import ParamsError
from vtube_planning.geometry.scene import load_scene
from vtube_planning.studies.study import ABLATIONS, Point, ablation_setup, narrowed, run_point
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
    config = SimConfig(time_limit_s=3.0)
    radii = {}
    for mode in ('planning', 'planned speed, (a3) off'):
        setup = s[mode]
        result = simulate(scene.tube, scene.swarm, setup.control, plan=setup.plan, config=config)
        radii[mode] = result.r_a_m
    assert np.all(radii['planned speed, (a3) off'] == scene.swarm.r_a_m)
    assert radii['planning'].max() > 1.2 * scene.swarm.r_a_m


def test_bad_grid_arguments(tmp_path, capsys) -> None:
    assert main(['ablation', '--out', str(tmp_path), '--sizes', '20,x']) == 2
    assert '--sizes must be comma-separated whole numbers >= 1' in capsys.readouterr().err
    assert main(['ablation', '--out', str(tmp_path), '--models', 'paper,fast']) == 2
    assert "axes.model holds 'fast'; choose from 'paper', 'acceleration limits'." in capsys.readouterr().err
    assert main(['ablation', '--out', str(tmp_path), '--saturations', 'clip']) == 2
    assert "axes.saturation holds 'clip'; choose from 'radial', 'forward'." in capsys.readouterr().err


def test_the_compensated_delay_is_the_runs_own_or_misjudged_by_a_period() -> None:
    assert Point('C', latency_steps=3, lag_s=0.1).compensated() == (0.0, 0.0)
    assert Point('C', latency_steps=3, lag_s=0.1, compensation='known').compensated() == (3.0, 0.1)
    assert Point('C', latency_steps=3, compensation='known-1').compensated() == (2.0, 0.0)
    assert Point('C', latency_steps=3, compensation='known+1').compensated() == (4.0, 0.0)
    assert Point('C', latency_steps=0, compensation='known-1').compensated() == (0.0, 0.0)  # never below 0
    with pytest.raises(ParamsError, match="the baseline 'flocking' does not fly"):
        run_point(Point('C', mode='flocking', latency_steps=2, compensation='known'))


def test_a_point_on_a_random_map_flies_that_maps_tube() -> None:
    from vtube_planning.geometry.from_maps.maps import scene_on_map

    point = Point('C', map='forest', map_seed=3, map_clutter=10)
    assert point.load_scene().tube.length_m == scene_on_map(load_scene('C'), 'forest', 3, clutter=10).tube.length_m
    assert Point('C').load_scene().tube.length_m == load_scene('C').tube.length_m  # no map: the scene's own tube
    assert point.load_scene().tube.length_m != load_scene('C').tube.length_m


def test_the_relaxed_mode_flies_the_plan_with_the_unplanned_swarms_freedom(setups) -> None:
    """'planning (relaxed)': the same scene's plan with freedom 'relaxed' (from v_max, (p3), (p4) left out), (a3) as in
    the paper's plan; a campaign may name it; the reports say what each mode's plan is held to."""
    from vtube_planning.studies.campaign import Campaign
    from vtube_planning.studies.study import FREEDOM_MODES, physics_text

    scene, s = setups
    relaxed = ablation_setup('planning (relaxed)', scene, scene.swarm, 0.02)
    assert relaxed.plan is not None and relaxed.control == s['planning'].control
    assert relaxed.plan.options == replace(scene.planning, freedom='relaxed')
    assert relaxed.plan.speed_mps[0] == scene.swarm.v_max_mps and relaxed.plan.time_s < s['planning'].plan.time_s
    campaign = Campaign.from_dict({'axes': {'scene': ['C'], 'mode': [*FREEDOM_MODES, 'no planning at v_max']}})
    assert [p.mode for p in campaign.points()] == ['planning (relaxed)', 'no planning at v_max']
    text = physics_text(['planning', 'planning (relaxed)', 'no planning at v_max', 'nmpc'])
    assert "planning: the paper's plan, (p3) from v_min and (p4); planning (relaxed): a plan from v_max" in text
    assert "no planning at v_max: v_max from the first period; nmpc: the baseline's own law." in text


def test_a_bend_no_robot_can_turn_fails_a_run_under_the_acceleration_limits(tmp_path) -> None:
    """A run under (2)-(4) in a tube with a bend no robot can turn fails, before it flies, with the refusal's words."""
    hairpin = '{ kind = "line", length_m = 20.0 }, { kind = "arc", radius_m = 1.0, angle_deg = 90.0 }'
    path = tmp_path / 'hairpin.toml'
    path.write_text(
        f'[tube.center]\npieces = [{hairpin}, {{ kind = "line", length_m = 20.0 }}]\n'
        '[tube.width]\nstart_m = 0.5\nparts = [{ kind = "constant" }]\n'
    )
    point = Point(str(path), mode='no planning', model='acceleration limits', n_robots=2)
    with pytest.raises(ParamsError, match='under the acceleration limits: the bend at l = 20.000..21.571 m'):
        run_point(point)
    from vtube_planning.studies.campaign import Campaign

    limited = Campaign.from_dict({'axes': {'scene': [str(path)], 'model': ['paper', 'acceleration limits']}})
    with pytest.raises(ParamsError, match='make the centre radius at least 2.834 m'):
        limited.points()  # before any run
    assert len(Campaign.from_dict({'axes': {'scene': [str(path)], 'model': ['paper']}}).points()) == 1


def test_a_narrowed_scene_ends_its_narrowing_at_the_width_given_and_keeps_the_rest() -> None:
    scene = load_scene('C')
    lengths = np.linspace(0.0, scene.tube.length_m, 241)
    own = scene.tube.half_width(lengths)
    assert narrowed(scene, 0.0) is scene
    for width in (0.9, 1.5):
        narrow = narrowed(scene, width)
        found = narrow.tube.half_width(lengths)
        assert found.min() == pytest.approx(width) and found[-1] == pytest.approx(width)
        before = lengths < 20.0  # the part before the narrowing (C.toml) is the scene's own
        assert np.array_equal(found[before], own[before])
        assert narrow.swarm == scene.swarm and narrow.planning == scene.planning and narrow.text == scene.text
        assert narrow.source != scene.source  # the plans of the process are cached by source
    assert Point('C', narrowest_m=0.9).load_scene().tube.half_width(lengths).min() == pytest.approx(0.9)
    with pytest.raises(ParamsError, match='narrowest_m = 4.5 needs a tube that narrows'):
        narrowed(scene, 4.5)
