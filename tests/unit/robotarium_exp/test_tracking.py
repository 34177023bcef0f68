"""What the filter did and how a run followed its plan, on a synthetic run whose errors are known by construction."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from robotarium_exp.tracking import (
    EXPANSION_THRESHOLD_M,
    FilterSummary,
    expansion_times,
    filter_summary,
    narrowing_start,
    plan_tracking,
)
from tests.unit.robotarium_exp.conftest import EXPANDS_AT, MARCH_DT
from vtube_planning.geometry.width import WidthPart, WidthProfile


def test_filter_summary_by_hand(trapezoid, marching) -> None:
    scene, _ = trapezoid
    a = marching
    v_min, v_max, length = scene.swarm.v_min_mps, scene.swarm.v_max_mps, scene.tube.length_m
    a['dxu'][:, 0, :] = 0.5 * (v_min + v_max)
    inside = np.flatnonzero((a['l_m'][:, 0] > 0.2) & (a['l_m'][:, 0] < length - 0.2))
    a['dxu'][inside[0], 0, 0] = 2 * v_max  # out of the band in the tube: counted
    a['dxu'][0, 0, 0] = 0.0  # before the entrance: not counted
    a['band_held'][inside[1]] = False
    a['dxu'][inside[1], 0, 1] = 0.0  # out of the band where it was dropped: only in band_share
    summary = filter_summary(a, v_min, v_max, length, MARCH_DT, failures=2)
    in_tube = int(((a['l_m'] >= 0) & (a['l_m'] <= length)).sum())
    n = a['l_m'].shape[1]
    assert summary == FilterSummary(
        correction_mean_mps=pytest.approx((a['barrier_correction_mps'].size * 0.01 + 0.04) / a['l_m'].size),
        correction_max_mps=0.05,
        intervention_m=pytest.approx((a['l_m'].size * 0.01 + 0.04) * MARCH_DT),
        band_share=pytest.approx(1 - 2 / in_tube),
        band_share_held=pytest.approx(1 - 1 / (in_tube - n)),
        band_dropped_share=pytest.approx(1 / a['t_s'].size),
        failures=2,
    )


def test_narrowing_start_is_where_the_half_width_first_drops(trapezoid) -> None:
    scene, _ = trapezoid
    start = narrowing_start(scene)
    first = scene.tube.width.parts[0]
    assert first.kind == 'constant' and start == pytest.approx(first.length_m)  # the trapezoid's entrance part ends
    h0 = float(scene.tube.half_width(0.0))
    assert float(scene.tube.half_width(start)) == pytest.approx(h0) and float(scene.tube.half_width(start + 1e-3)) < h0
    straight = WidthProfile(h0, (WidthPart('constant', scene.tube.length_m),))
    assert narrowing_start(replace(scene, tube=replace(scene.tube, width=straight))) == scene.tube.length_m


def test_expansion_and_front_at_the_narrowing(trapezoid, marching) -> None:
    scene, _ = trapezoid
    t = marching['t_s']
    expansion, front = expansion_times(marching, scene)
    assert expansion == t[EXPANDS_AT]
    first = np.flatnonzero(marching['l_m'].max(axis=1) >= narrowing_start(scene))[0]
    assert front == t[first] and marching['l_m'][first - 1].max() < narrowing_start(scene)
    marching['r_a_m'][EXPANDS_AT:] -= 0.03 - 0.5 * EXPANSION_THRESHOLD_M  # below the threshold: never
    assert expansion_times(marching, scene)[0] is None
    del marching['r_a_m']  # a recording of the poses alone: no expansion time, the front's as before
    assert expansion_times(marching, scene) == (None, front)


def test_plan_tracking_finds_the_errors_put_in(trapezoid, marching) -> None:
    """Density 10 % above the plan and the plan's speed: errors 0.1 and 0 in every phase; the phases split the
    steps by the swarm's centre at the span where (p7) binds."""
    scene, plan = trapezoid
    tracked = plan_tracking(marching, plan, scene)
    active = plan.l_m[plan.active['p7']]
    assert tracked.p7_active_m == (active.min(), active.max())
    center = marching['l_m'].mean(axis=1)
    expected_steps = {
        'approach': ((center >= 0) & (center < active.min())).sum(),
        'dip': ((center >= active.min()) & (center <= active.max())).sum(),
        'narrow': ((center > active.max()) & (center <= scene.tube.length_m)).sum(),
    }
    for name, phase in tracked.phases().items():
        assert phase.steps == expected_steps[name] > 0
        assert phase.density_error_mean == pytest.approx(0.1) and phase.density_error_max == pytest.approx(0.1)
        assert phase.speed_error_mean == pytest.approx(0.0, abs=1e-12) and phase.speed_error_max < 1e-12
    assert (tracked.expansion_start_s, tracked.front_at_narrowing_s) == expansion_times(marching, scene)
    data = tracked.to_json()
    assert json.loads(json.dumps(data, allow_nan=False)) == data and data['dip']['steps'] == expected_steps['dip']


def test_a_phase_without_steps_and_a_parked_swarm_give_none(trapezoid, marching) -> None:
    scene, plan = trapezoid
    marching['flying'][:, 0] = False  # a robot parked from the start: no step counts
    tracked = plan_tracking(marching, plan, scene)
    for phase in tracked.phases().values():
        assert phase.steps == 0 and phase.density_error_mean is None and phase.speed_error_max is None
    assert tracked.to_json()['approach']['density_error_mean'] is None
