"""The analysis on real third-party recordings, checked against numbers recomputed here from the raw samples.

The oracles use plain numpy on the samples as the files give them (no vtube function): the frames walked through
the stamps in a loop, np.interp between two samples no more than three median periods apart (a sample in a frame
otherwise taken as it is), and distances and tube positions of a straight tube worked out by hand. Skipped, with the reason, when the recordings are not beside the repository.
"""

from __future__ import annotations

from itertools import combinations

import numpy as np
import pytest

from robotarium_exp.analysis.loaders import load_trajectory
from robotarium_exp.analysis.report import analyse
from robotarium_exp.errors import AnalysisError
from tests.support.realdata import (
    MRCLAM_ROBOTS,
    mrclam_samples,
    realdata_folder,
    write_mrclam_ros1,
    write_mrclam_tf,
)
from vtube_planning.geometry.scene import scene_from_text

REALDATA = realdata_folder()
pytestmark = [
    pytest.mark.skipif(
        REALDATA is None, reason='the real recordings are not at ../shared/realdata and $VTUBE_REALDATA is not set'
    ),
]
RADIUS_M = 0.35  # an iRobot Create is 0.33 m across


def oracle_frames(samples: dict[str, tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, int]:
    """Frames: going through the stamps in time, each frame takes the stamps less than half the shortest median
    sampling period after its first one; and that window."""
    window = min(int(np.median(np.diff(s))) for s, _ in samples.values()) // 2
    frames: list[int] = []
    for stamp in sorted({int(t) for s, _ in samples.values() for t in s}):
        if not frames or stamp >= frames[-1] + window:
            frames.append(stamp)
    return np.array(frames, dtype=np.int64), window


def oracle_positions(samples: dict[str, tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Frames (:func:`oracle_frames`) and each robot's positions there: at its own stamps, interpolated between two
    of its samples at most three median periods apart; in a frame without either, its first sample in the frame;
    NaN elsewhere."""
    frames, _ = oracle_frames(samples)
    out = {}
    for robot, (stamps, values) in samples.items():
        limit = 3 * np.median(np.diff(stamps))
        since = (frames - frames[0]).astype(float), (stamps - frames[0]).astype(float)  # exact as floats
        x, y = (np.interp(*since, values[:, k]) for k in (0, 1))
        nxt = np.minimum(np.searchsorted(stamps, frames), stamps.size - 1)  # first sample at or after
        on = stamps[nxt] == frames
        inner = (frames > stamps[0]) & (frames < stamps[-1]) & ~on
        ok = on | (inner & (stamps[nxt] - stamps[np.maximum(nxt - 1, 0)] <= limit))
        where = np.where(ok[:, None], np.column_stack([x, y]), np.nan)
        for stamp, value in zip(stamps.tolist(), values[:, :2], strict=True):
            frame = int(np.searchsorted(frames, stamp, side='right')) - 1
            if np.isnan(where[frame, 0]):
                where[frame] = value
        out[robot] = where
    return frames, out


@pytest.fixture(scope='module')
def mrclam(tmp_path_factory) -> dict:
    samples = mrclam_samples(REALDATA)
    folder = tmp_path_factory.mktemp('mrclam')
    frames, where = oracle_positions({r: (s, v[:, :2]) for r, (s, v) in samples.items()})
    pairs = {}
    for a, b in combinations(MRCLAM_ROBOTS, 2):
        d = np.hypot(*(where[a] - where[b]).T)
        pairs[(a, b)] = (np.nanmin(d), frames[np.nanargmin(d)], int(np.isfinite(d).sum()))
    ros1 = write_mrclam_ros1(samples, folder / 'vrpn.bag')
    tf = write_mrclam_tf(samples, folder / 'tf')
    return {'samples': samples, 'frames': frames, 'pairs': pairs, 'ros1': load_trajectory([ros1]), 'tf': tf}


@pytest.mark.parametrize('kind', ['ros1', 'tf'])
def test_mrclam_robots_frames_gaps_and_the_collision_after_one_log_ends(mrclam, kind: str) -> None:
    trajectory = mrclam['ros1'] if kind == 'ros1' else load_trajectory([mrclam['tf']])
    samples = mrclam['samples']
    assert trajectory.robot_ids == MRCLAM_ROBOTS
    assert trajectory.t_s.size == mrclam['frames'].size
    for robot, (stamps, _) in samples.items():
        steps = np.diff(stamps)
        expected = int((steps > 3 * np.median(steps)).sum())  # integers: a hole of exactly 3 periods is no gap
        assert sum(g.robot == robot for g in trajectory.gaps) == expected
        assert int((steps == 3 * np.median(steps)).sum()) > 0  # such holes exist in this set
    coverage = {c.robot: c for c in trajectory.coverage}
    assert [coverage[r].samples for r in MRCLAM_ROBOTS] == [s.size for s, _ in samples.values()]
    ends = {r: (s[-1] - mrclam['frames'][0]) * 1e-9 for r, (s, _) in samples.items()}
    assert coverage['Robot1'].last_s == pytest.approx(ends['Robot1'], abs=1e-9)
    assert min(ends.values()) < max(ends.values()) - 120  # Robot1's log ends about 128 s early
    m = analyse(trajectory, collision_distance_m=RADIUS_M).metrics.to_json()
    (a, b), (d, t_ns, _) = min(mrclam['pairs'].items(), key=lambda kv: kv[1][0])
    assert m['min_distance_pair'] == [a, b]
    assert m['min_distance_m'] == pytest.approx(d, abs=1e-9)
    assert m['min_distance_time_s'] == pytest.approx((t_ns - mrclam['frames'][0]) * 1e-9, abs=1e-6)
    assert m['min_distance_time_s'] > ends['Robot1']  # in the stretch after Robot1's log ended
    for pair in m['pairs']:
        expected_d, _, common = mrclam['pairs'][tuple(pair['robots'])]
        assert pair['min_distance_m'] == pytest.approx(expected_d, abs=1e-9)
        assert pair['common_frames'] == common
    colliding = sorted(list(p) for p, (d, _, _) in mrclam['pairs'].items() if d < RADIUS_M)
    assert colliding and m['colliding_pairs'] == colliding
    # the minimum over only the frames every robot covers misses it (the old answer, 0.429 m)
    all_present = np.all([np.isfinite(trajectory.positions_m[:, 0, k]) for k in range(5)], axis=0)
    p = trajectory.positions_m[all_present]
    restricted = min(np.hypot(*(p[:, :, i] - p[:, :, j]).T).min() for i, j in combinations(range(5), 2))
    assert restricted > RADIUS_M > m['min_distance_m']


def test_mrclam_pairs_measured_without_interpolation_agree(mrclam) -> None:
    """At the stamps two robots share, their distance needs no interpolation; a frame takes them at its first stamp,
    at most the window earlier, so the pair's minimum is never above theirs by more than the robots move meanwhile."""
    m = analyse(mrclam['ros1']).metrics.to_json()
    assert m['collision_pairs'] is None and 'passage' not in m  # no scene, no radius: tube-free metrics only
    samples = mrclam['samples']
    _, window = oracle_frames(samples)
    for pair in m['pairs']:
        (sa, va), (sb, vb) = samples[pair['robots'][0]], samples[pair['robots'][1]]
        _, ia, ib = np.intersect1d(sa, sb, return_indices=True)
        raw = np.hypot(*(va[ia, :2] - vb[ib, :2]).T).min()
        speed = max(np.max(np.hypot(*np.diff(v[:, :2], axis=0).T) / np.diff(s) * 1e9) for s, v in ((sa, va), (sb, vb)))
        assert pair['min_distance_m'] <= raw + 2 * speed * window * 1e-9 + 1e-12


def test_mrclam_tf_lists_the_static_frame_and_the_unread_topic(mrclam, tmp_path) -> None:
    """On the first 2000 samples of each robot (what is listed does not need the whole set)."""
    head = {robot: (stamps[:2000], values[:2000]) for robot, (stamps, values) in mrclam['samples'].items()}
    tf = write_mrclam_tf(head, tmp_path / 'tf_head')
    trajectory = load_trajectory([tf], frame_pattern=r'^(?P<robot>Robot[1-4])$')
    assert trajectory.robot_ids == MRCLAM_ROBOTS[:4]
    ignored = trajectory.source['ignored']
    assert {'topic': '/tf_static', 'frame': 'vicon', 'reason': 'static transform'} in ignored
    assert any(i['topic'] == '/battery' and 'is not read' in i['reason'] for i in ignored)
    assert any(i.get('frame') == 'Robot5' and 'frame pattern' in i['reason'] for i in ignored)
    assert trajectory.source['world_frame'] == 'world'


def straight_scene(x0: float, y0: float, heading_deg: float, length_m: float, half_width_m: float):
    """A straight tube of constant width: arc length and lateral offset by hand (:func:`oracle_observed`)."""
    text = (
        f'[tube.center]\nstart_xy_m = [{x0}, {y0}]\nheading_deg = {heading_deg}\n'
        f'pieces = [{{ kind = "line", length_m = {length_m} }}]\n\n'
        f'[tube.width]\nstart_m = {half_width_m}\nparts = [{{ kind = "constant" }}]\n'
    )
    return scene_from_text(text, name='straight', source='test')


def oracle_observed(
    t_s: np.ndarray, where: dict[str, np.ndarray], x0: float, y0: float, heading_deg: float, length: float, w: float
) -> dict:
    """Which parts of the passage the frames show, and the passing time when all do, on a straight tube."""
    c, s = np.cos(np.radians(heading_deg)), np.sin(np.radians(heading_deg))
    l_m = {r: (p[:, 0] - x0) * c + (p[:, 1] - y0) * s for r, p in where.items()}
    lateral = {r: -(p[:, 0] - x0) * s + (p[:, 1] - y0) * c for r, p in where.items()}
    inside = {r: (l_m[r] >= 0) & (l_m[r] <= length) & (np.abs(lateral[r]) <= w) for r in where}
    reached = np.any([l >= 0 for l in l_m.values()], axis=0)
    first = int(np.argmax(reached))
    before = any((l[:first] < 0).any() for l in l_m.values())
    never = tuple(r for r in where if not inside[r].any())
    exits = {}
    for r in where:
        after = np.flatnonzero(l_m[r] >= length)
        after = after[after > np.argmax(inside[r])] if inside[r].any() else after[:0]
        if after.size:
            exits[r] = t_s[after[0]]
    whole = before and not never and len(exits) == len(where)
    return {
        'entrance': before,
        'never_inside': never,
        'exited': tuple(exits),
        'passing_time_s': max(exits.values()) - t_s[first] if whole else None,
    }


@pytest.mark.parametrize(
    ('tube', 'observed'),
    [
        ((-0.5, 0.0, 0.0, 2.0, 0.3), False),  # the bodies cross the tube's span but never within its width
        ((1.15, -3.5, -90.0, 0.4, 0.5), True),  # both bodies seen before, inside, and past the exit
    ],
)
def test_passage_observability_on_two_tracked_bodies(tube, observed) -> None:
    from rosbags.highlevel import AnyReader

    bag = REALDATA / 'acl-mocap2' / 'mocap.bag'
    raw: dict[str, tuple[list, list]] = {}
    with AnyReader([bag]) as reader:
        for c, _, data in reader.messages(connections=reader.connections):
            m = reader.deserialize(data, c.msgtype)
            stamps, xy = raw.setdefault(c.topic.split('/')[1], ([], []))
            stamps.append(m.header.stamp.sec * 10**9 + m.header.stamp.nanosec)
            xy.append((m.pose.position.x, m.pose.position.y))
    samples = {r: (np.array(s, dtype=np.int64), np.array(p)) for r, (s, p) in sorted(raw.items())}
    frames, where = oracle_positions(samples)
    scene = straight_scene(*tube)
    trajectory = load_trajectory([bag], topic_pattern=r'^/(?P<robot>[^/]+)/world$')
    assert trajectory.t_s.size == frames.size
    assert len(trajectory.gaps) == sum(int((np.diff(s) > 3 * np.median(np.diff(s))).sum()) for s, _ in samples.values())
    m = analyse(trajectory, scene).metrics.to_json()
    truth = oracle_observed((frames - frames[0]) * 1e-9, where, *tube)
    passage = m['passage']
    assert passage['entrance_observed'] == truth['entrance']
    assert tuple(passage['never_inside']) == truth['never_inside']
    assert m['robots_passed'] == len(truth['exited'])
    assert (truth['passing_time_s'] is not None) == observed
    if observed:
        assert m['passing_time_s'] == pytest.approx(truth['passing_time_s'], abs=1e-6)
        assert passage['unobserved'] == []
    else:
        assert truth['never_inside'] == tuple(samples) and m['passing_time_s'] is None
        assert 'never seen inside the tube' in ' '.join(passage['unobserved'])


def test_evo_tf_bags_robot_is_the_moving_frame() -> None:
    folder = REALDATA / 'evo-tf'
    for bag in (folder / 'tf_example.bag', folder / 'tf_example'):
        trajectory = load_trajectory([bag])
        assert trajectory.robot_ids == ('base_footprint',)
        assert trajectory.source['world_frame'] == 'odom'
        assert {'topic': '/tf_static', 'frame': 'base_link', 'reason': 'static transform'} in trajectory.source[
            'ignored'
        ]
    with pytest.raises(AnalysisError, match='different reference frames.*--world-frame'):
        load_trajectory([folder / 'nav2_turtlebot.mcap'])
    trajectory = load_trajectory([folder / 'nav2_turtlebot.mcap'], world_frame='odom')  # a bare MCAP file
    assert trajectory.robot_ids == ('base_link',)
    reasons = {(i['topic'], i.get('frame')): i['reason'] for i in trajectory.source['ignored']}
    assert reasons[('/tf', 'odom')] == "pose in frame 'map', not the world frame 'odom'"
    assert reasons[('/tf', 'left_wheel')] == 'does not move'
    assert 'is not read' in reasons[('/amcl_pose', None)]


def test_bare_mcap_in_a_folder_without_metadata(tmp_path) -> None:
    folder = tmp_path / 'copy'
    folder.mkdir()
    (folder / 'nav2.mcap').write_bytes((REALDATA / 'evo-tf' / 'nav2_turtlebot.mcap').read_bytes())
    assert load_trajectory([folder], world_frame='odom').robot_ids == ('base_link',)


def test_robotarium_mat_files_read_like_their_converted_npy() -> None:
    folder = REALDATA / 'robotarium-lines3'
    mats = sorted(folder.glob('*.mat'))
    for k, mat in enumerate(mats, start=1):
        from_mat = load_trajectory([mat])
        poses = np.load(folder / f'run{k}' / 'vtube_poses.npy')
        np.testing.assert_array_equal(from_mat.positions_m, poses[:, :2])
        assert 'does not increase' in from_mat.source['time']
        np.testing.assert_allclose(from_mat.t_s, np.load(folder / f'run{k}' / 'vtube_t.npy'), atol=1e-9)
    with pytest.raises(AnalysisError, match=r"class objects.*save\('poses.mat', 'x', '-v7'\)"):
        load_trajectory([REALDATA / 'robotarium-cbf4' / 'robotarium2_data.mat'])


def test_report_records_inputs_options_and_is_strict_json(tmp_path) -> None:
    import hashlib
    import json

    from vtube.cli import main

    bag = REALDATA / 'acl-uwb3' / 'uwb.bag'
    args = ['analyze', str(bag), '--out', str(tmp_path), '--topic-pattern', r'^/(?P<robot>[^/]+)/world$']
    assert main([*args, '--max-gap', '0.05s', '--scene', 'robotarium_trapezoid']) == 0
    text = (tmp_path / 'metrics.json').read_text()
    m = json.loads(text, parse_constant=lambda c: pytest.fail(f'{c} in metrics.json'))['data']
    assert m['inputs'] == [
        {'path': str(bag), 'bytes': bag.stat().st_size, 'sha256': hashlib.sha256(bag.read_bytes()).hexdigest()}
    ]
    assert m['options']['max_gap'] == '0.05s' and m['vtube_version']
    assert len([i for i in m['source']['ignored'] if 'is not read' in i['reason']]) == 18
    assert m['passing_time_s'] is None and m['passage']['unobserved']


def test_the_testbed_identification_finds_a_delay_of_3_to_7_iterations_on_robotarium_cbf4() -> None:
    """The recorded commands and poses of a real 4-robot run: the least-squares delay of both channels is 3-7
    iterations, and with it the speed gain is near 1 (the identification of benchmarks/testbed_identification.py)."""
    from benchmarks.testbed_identification import fit_channel, per_robot
    from benchmarks.testbed_runs import read_run

    run = read_run(REALDATA / 'robotarium-cbf4' / 'robotarium2_data.mat')
    assert run is not None and run.poses.shape == (5000, 3, 4) and run.commands.shape == (5000, 2, 4)
    for channel in (0, 1):
        delay, lag, _ = fit_channel([run], channel)
        assert 3 <= delay <= 7 and 0 < lag < 0.5
    gains = per_robot([run], 0, *fit_channel([run], 0)[:2])[:, 0]
    assert np.all(np.abs(gains - 1) < 0.1)


def test_the_pose_side_of_real_runs_stale_while_standing_and_stalls_that_drive_on() -> None:
    """robotarium-cbf4 and robotarium-lines3 (none of them scaled after saving): a robot actually driving repeats a
    pose in under 1 % of its iterations, one standing in most; its big steps lie along the heading and stay."""
    from benchmarks.testbed_identification import scaled_after_saving, stale_and_jumps, stale_by_motion, stalls
    from benchmarks.testbed_runs import default_files, load_runs

    runs = load_runs(default_files(None))
    assert len(runs) == 6 and not any(scaled_after_saving(run) for run in runs)
    stale = stale_by_motion(runs)
    assert stale['driving'] < 0.01 and stale['stopped'] > 0.3
    assert stale_and_jumps(runs)['stale_moving'] > 2 * stale['driving']  # by the commands, driving robots look stale
    found = stalls(runs)
    assert found['continued'] > 0.8 and found['along'] > 0.8 and found['extra_steps'] > 1


def test_a_run_whose_commands_were_scaled_after_saving_is_found() -> None:
    """Synthetic: a robot driving circles through all four quadrants with the model's response to its commands;
    the same run with the velocities times 0.8 in the quadrant x < 0, y > 0 is found, the plain one is not."""
    from benchmarks.testbed_identification import response, scaled_after_saving
    from benchmarks.testbed_runs import DT, Run

    rng = np.random.default_rng(3)
    steps = 3000
    u = np.stack([0.1 + 0.02 * rng.standard_normal(steps), 0.4 + 0.3 * rng.standard_normal(steps)], axis=1)
    for scale, found in ((1.0, False), (0.8, True)):
        poses = np.zeros((steps, 3, 1))
        poses[0, :, 0] = [0.0, -0.2, 0.0]
        v, w = response(u[:, :1], 5.0, 0.19)[:, 0], response(u[:, 1:], 5.0, 0.19)[:, 0]
        for k in range(steps - 1):
            x, y, th = poses[k, :, 0]
            g = scale if (x < 0 and y > 0) else 1.0
            poses[k + 1, :, 0] = [x + DT * g * v[k] * np.cos(th), y + DT * g * v[k] * np.sin(th), th + DT * g * w[k]]
        assert scaled_after_saving(Run('synthetic', poses, u[:, :, None])) == found
