"""The replay's data: the frames it plays (an independent recount), the robots' positions and radii at those frames,
the panels, and text from the files that cannot escape the page's JSON."""

from __future__ import annotations

import html
import json
import math
import re
from dataclasses import replace
from fractions import Fraction

import numpy as np
import pytest

from robotarium_exp.analysis.loaders import load_trajectory
from robotarium_exp.analysis.passage import along_tube
from robotarium_exp.analysis.replay import (
    MAX_FPS,
    check_page,
    embed,
    flew_a_plan,
    millimetres,
    playback_frames,
    recorded_avoidance_radii,
    replay_data,
    replay_html,
    replayed_scene,
    write_replay,
)
from robotarium_exp.errors import AnalysisError
from vtube_planning.geometry.scene import load_scene
from vtube_planning.log import LOG_FORMAT, LOG_VERSION
from vtube_planning.npzfile import write_npz
from vtube_planning.planning.planner import plan_convex

ROBOTS = 12  # more than ten: the loader's robot ids sort as robot_0, robot_1, robot_10, ..., not as the log's columns
HOSTILE = '</script><script>alert(1)</script><!-- & "quoted"'


@pytest.fixture(scope='module')
def run(tmp_path_factory):
    """A log of twelve robots crossing scene A in 8 s at 50 Hz, each with its own r_a, one robot missing for a
    while; the scene, its plan, and the log read."""
    scene = load_scene('A')
    t = 0.02 * np.arange(400)
    k = np.arange(ROBOTS)
    x = -4.0 + 6.0 * t[:, None] + 0.7 * (k % 4)[None, :]
    y = np.broadcast_to(0.8 * (k // 4 - 1.0), x.shape)
    positions = np.stack([x, y], axis=1)  # (T, 2, N)
    positions[100:130, :, 5] = np.nan
    r_a = 0.8 + 0.01 * k[None, :] + 0.001 * np.arange(t.size)[:, None]
    log = tmp_path_factory.mktemp('replay') / 'log.npz'
    meta = {'format': LOG_FORMAT, 'version': LOG_VERSION, 'kind': 'simulation', 'scene': 'A', 'planned': True}
    write_npz(log, {'t_s': t, 'positions_m': positions, 'r_a_m': r_a}, meta)
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene='A')
    return scene, plan, load_trajectory([log]), positions, r_a


def test_the_frames_played_are_the_first_of_each_thirtieth_of_a_second_at_50_hz() -> None:
    t = 0.02 * np.arange(910)
    # the first frame i of bin k (i / 50 >= k / 30), for every bin up to the last frame's, counted exactly
    expected = sorted({math.ceil(Fraction(5 * k, 3)) for k in range(math.floor(Fraction(909, 50) * 30) + 1)})
    assert playback_frames(t).tolist() == expected
    assert len(expected) == 546


def test_the_frames_played_of_irregular_stamps_match_a_recount_in_integers() -> None:
    rng = np.random.default_rng(3)
    ms = np.unique(rng.integers(0, 20_000, 3000))  # whole milliseconds: the bins counted without floats
    ms = np.concatenate([ms, 100 * np.arange(200)])  # and every bin boundary that is a whole millisecond
    ms = np.unique(ms)
    expected, bins = [], set()
    for i, m in enumerate(ms.tolist()):
        if m * MAX_FPS // 1000 not in bins:
            bins.add(m * MAX_FPS // 1000)
            expected.append(i)
    kept = playback_frames(ms / 1000.0)
    assert kept.tolist() == expected
    assert np.bincount((ms[kept] * MAX_FPS // 1000).astype(int)).max() == 1  # at most MAX_FPS a second


def test_millimetres_round_and_keep_holes() -> None:
    assert millimetres([[0.0004, -1.2346], [np.nan, 2.0]]) == [[0, -1235], [None, 2000]]


def test_the_page_holds_each_robot_where_the_trajectory_has_it_at_the_frames_played(run) -> None:
    scene, plan, trajectory, positions, r_a = run
    data = replay_data(trajectory, scene, plan, 'the plan')
    frames = playback_frames(trajectory.t_s)
    assert len(data['xy']) == len(data['t']) == frames.size == 240  # 8 s at most 30 a second, of 400
    columns = [int(rid.removeprefix('robot_')) for rid in trajectory.robot_ids]
    assert columns[:4] == [0, 1, 10, 11]
    for j, f in enumerate(frames):
        assert data['t'][j] == round(float(trajectory.t_s[f]), 3)
        for i, column in enumerate(columns):
            x, y = positions[f, :, column]
            expected = [None, None] if np.isnan(x) else [round(1000 * x), round(1000 * y)]
            assert data['xy'][j][2 * i : 2 * i + 2] == expected
            assert data['r_a'][j][i] == round(1000 * r_a[f, column])
    assert data['robots'] == list(trajectory.robot_ids) and data['r_p_m'] == scene.swarm.r_p_m
    assert len(data['tube']['left']) == len(data['tube']['center']) == 400 and data['obstacles'] == []


def test_the_panels_are_the_measures_along_the_tube_and_the_plan_at_the_swarm_centre(run) -> None:
    scene, plan, trajectory, _, _ = run
    frames = playback_frames(trajectory.t_s)
    along = along_tube(trajectory, scene)
    density, speed = replay_data(trajectory, scene, plan, 'the plan')['panels']
    for j, f in enumerate(frames):
        if not along.complete[f]:
            assert density['measured'][j] is None and speed['measured'][j] is None
            continue
        assert density['measured'][j] == pytest.approx(along.density_per_m2[f], rel=1e-3)
        mean = along.forward_speed_mps[f].mean()  # NaN next to a hole: the speed is a central difference
        assert speed['measured'][j] is None if np.isnan(mean) else speed['measured'][j] == pytest.approx(mean, rel=1e-3)
        center = along.l_m[f].mean()
        if 0.0 <= center <= scene.tube.length_m:
            assert speed['planned'][j] == pytest.approx(float(plan.speed(np.array([center]))[0]), rel=1e-3)
            assert density['planned'][j] == pytest.approx(float(plan.density(np.array([center]))[0]), rel=1e-3)
        else:
            assert speed['planned'][j] is None
    assert any(v is not None for v in speed['planned'])
    assert all(p['planned'] is None for p in replay_data(trajectory, scene, None, '')['panels'])


def test_the_recorded_radii_only_from_a_log_whose_rows_are_the_frames(run) -> None:
    _, _, trajectory, _, _ = run
    assert recorded_avoidance_radii(trajectory) is not None
    assert recorded_avoidance_radii(replace(trajectory, source={**trajectory.source, 'kind': 'ros bag'})) is None
    assert recorded_avoidance_radii(replace(trajectory, t_s=trajectory.t_s * 2)) is None


def test_text_from_the_files_stays_data(run) -> None:
    scene, plan, trajectory, _, _ = run
    hostile = replace(trajectory, robot_ids=(HOSTILE, *trajectory.robot_ids[1:]), source={'path': HOSTILE})
    page = replay_html(replay_data(hostile, scene, plan, 'the plan'))
    assert page.count('</script>') == 2 and '<script>alert' not in page  # the template's two elements only
    embedded = re.search(r'<script id="replay-data" type="application/json">(.*?)</script>', page, re.DOTALL)
    assert embedded is not None
    data = json.loads(embedded.group(1))
    assert data['robots'][0] == HOSTILE and data['title'].endswith(HOSTILE)
    assert f'<title>{html.escape(data["title"])}</title>' in page
    text = embed({'s': HOSTILE})
    assert not set('<>&') & set(text) and json.loads(text) == {'s': HOSTILE}


def test_the_scene_plan_and_page_are_checked(run, tmp_path) -> None:
    scene, plan, trajectory, _, _ = run
    assert replayed_scene(trajectory, None) == 'A' and replayed_scene(trajectory, 'B') == 'B'
    with pytest.raises(AnalysisError, match='records no scene, and the replay draws the tube: give'):
        replayed_scene(replace(trajectory, source={'path': 'x'}), None)
    assert flew_a_plan(trajectory) and not flew_a_plan(replace(trajectory, source={'planned': False}))
    for bad in (tmp_path / 'run.png', tmp_path):
        with pytest.raises(AnalysisError, match='is not an .html file'):
            check_page(bad)
    written = write_replay(trajectory, scene, plan, tmp_path / 'run.html')
    assert written.size_bytes == (tmp_path / 'run.html').stat().st_size
    assert (written.frames, written.frames_in_run, written.robots, written.duration_s) == (240, 400, 12, 7.98)
