"""``vtube analyze``: its options handed to the pipeline, and the view of what was measured."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from vtube import pipeline
from vtube.cli.analyze import analyze_view
from vtube.cli.app import main


def analysed(
    *,
    robots: int = 3,
    closest=True,
    collision_m: float | None = 0.27,
    tube=True,
    failures=(),
    clearances=None,
    apart=(None, None),
) -> pipeline.Analysed:
    passage = SimpleNamespace(
        passing_time_s=None if tube == 'unobserved' else 41.234, unobserved=['the exit'], start='start inferred'
    )
    metrics = SimpleNamespace(
        frames=120,
        complete_frames=100,
        gaps=[1, 2],
        closest=SimpleNamespace(robots=('r1', 'r2'), min_distance_m=0.31234, time_s=12.345) if closest else None,
        collision_pairs=0,
        collision_distance_m=collision_m,
        tube=SimpleNamespace(
            passage=passage,
            tube_violation_steps=7,
            violations_counted=lambda: 'the centre',
            obstacle_clearance_m=clearances,
            closest_in_passage=apart[0],
            closest_after_passage=apart[1],
        )
        if tube
        else None,
        robot_ids=('r1', 'r2', 'r3')[:robots],
        to_json=lambda: {'robots': robots},
        failures=lambda: failures,
    )
    source = {'kind': 'ros bag', 'path': 'b.mcap', 'ignored': ['/tf_static']}
    data = SimpleNamespace(trajectory=SimpleNamespace(source=source, n_robots=robots), metrics=metrics)
    scene = SimpleNamespace(name='robotarium_curve') if tube else None
    return pipeline.Analysed(scene, data, None, Path('a/report.md'), Path('a/metrics.json'))


def test_the_view_of_an_analysis_in_a_scene() -> None:
    view = analyze_view(analysed())
    assert view.lines == (
        (
            'analysis of ros bag b.mcap in scene robotarium_curve: 3 robots, 120 frames (100 with every robot), 2 gaps, '
            '1 topics/frames/variables ignored'
        ),
        '  minimum distance 0.312 m (r1 and r2, t = 12.35 s), 0 pairs closer than 0.270 m',
        '  passing time 41.23 s (start inferred)',
        '  7 tube violations (robot-frames, the centre)',
        '  written a/report.md, a/metrics.json',
    )
    assert view.data == {'robots': 3}


def test_the_closest_approach_to_an_obstacle_is_said_when_the_scene_has_obstacles() -> None:
    lines = analyze_view(analysed(clearances=(0.3, None, 0.12))).lines
    assert lines[-2] == '  closest approach to an obstacle 0.120 m (r3), the centre'
    assert not any('obstacle' in line for line in analyze_view(analysed()).lines)


def test_a_failed_passage_is_said_and_exits_1() -> None:
    view = analyze_view(analysed(failures=('robots r3 never passed the exit',)))
    assert view.lines[-2] == '  FAILED: robots r3 never passed the exit' and view.exit_code == 1
    assert analyze_view(analysed()).exit_code == 0


def test_the_view_without_a_tube_distances_or_passage() -> None:
    lines = analyze_view(analysed(robots=1, closest=False, collision_m=None, tube=False)).lines
    assert 'without a tube' in lines[0]
    assert lines[1] == '  one robot: no distances, collisions not counted (give --collision-distance)'
    assert len(lines) == 3
    apart = analyze_view(analysed(closest=False, tube='unobserved')).lines
    assert (
        apart[1].startswith('  no two robots seen at the same time')
        and apart[2] == '  no passing time: the exit (start inferred)'
    )


def test_the_options_reach_the_pipeline(tmp_path, monkeypatch, capsys) -> None:
    calls = []

    def analyse_data(inputs, out, options):
        calls.append((inputs, out, options))
        return analysed()

    monkeypatch.setattr(pipeline, 'analyse_data', analyse_data)
    args = ['analyze', 'x.mcap', 'y', '--scene', 'robotarium_curve', '--out', str(tmp_path), '--plan', 'p.npz']
    args += ['--topic', '/a', '--topic', '/b', '--topic-pattern', '/(?P<robot>.+)/pose', '--world-frame', 'map']
    assert main([*args, '--max-gap', '0.25s', '--collision-distance', '0.3', '--compare', 'log.npz']) == 0
    inputs, out, options = calls[0]
    assert inputs == [Path('x.mcap'), Path('y')] and out == tmp_path
    assert options == pipeline.AnalysisOptions(
        scene='robotarium_curve',
        plan_file=Path('p.npz'),
        compare=Path('log.npz'),
        topic_pattern='/(?P<robot>.+)/pose',
        frame_pattern=None,
        topics=('/a', '/b'),
        world_frame='map',
        max_gap='0.25s',
        collision_distance_m=0.3,
    )
    assert 'analysis of ros bag' in capsys.readouterr().out


def test_a_plan_needs_its_scene(tmp_path, capsys) -> None:
    assert main(['analyze', 'x', '--out', str(tmp_path), '--plan', 'p.npz']) == 2
    assert capsys.readouterr().err == 'error: --plan needs the scene it was made for (--scene).\n'
    assert main(['analyze', str(tmp_path / 'nothing'), '--scene', 'robotarium_trapezoid', '--out', str(tmp_path)]) == 2
    assert capsys.readouterr().err.startswith('error: ')


def test_the_minimum_distance_in_the_passage_and_while_parking_are_said_apart() -> None:
    """Issue 49: the demo's 0.173 m at 63.9 s was measured while parking, unlabelled."""
    lines = analyze_view(analysed(apart=((0.221, 32.08), (0.173, 63.86)))).lines
    assert lines[2] == (
        '  minimum distance up to the last exit (passage) 0.221 m (t = 32.08 s), after it (parking) 0.173 m '
        '(t = 63.86 s)'
    )
    alone = analyze_view(analysed(apart=((0.221, 32.08), None))).lines
    assert alone[2] == '  minimum distance up to the last exit (passage) 0.221 m (t = 32.08 s)'
    assert not any('up to the last exit' in line for line in analyze_view(analysed()).lines)


def test_a_file_cut_in_a_save_is_said() -> None:
    """Issue 49: the frames before a cut are analysed, and the cut is said below the first line."""
    done = analysed()
    done.data.trajectory.source['cut'] = ['vtube_poses.npy: cut in a save after 4 whole frames; those are analysed']
    assert analyze_view(done).lines[1] == '  vtube_poses.npy: cut in a save after 4 whole frames; those are analysed'
