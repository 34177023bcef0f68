"""The metrics' types: collisions counted or not, the tube's keys only with a tube, strict JSON."""

from __future__ import annotations

import json
import math

from robotarium_exp.analysis.loaders import InputFile
from robotarium_exp.analysis.metrics import PairMeasure, RecordingMetrics, TrackingErrors, TubeMetrics
from robotarium_exp.analysis.passage import Passage
from robotarium_exp.analysis.trajectory import Gap

PAIRS = (
    PairMeasure(('a', 'b'), 10, 0.12, 1.5, 3),
    PairMeasure(('a', 'c'), 0, None, None, 0),
    PairMeasure(('b', 'c'), 8, 0.4, 0.2, 0),
)
UNCOUNTED = tuple(PairMeasure(p.robots, p.common_frames, p.min_distance_m, p.time_s, None) for p in PAIRS)
PASSAGE = Passage(12.0, 1.0, 13.0, True, (), (), 3, ())


def metrics(collision: float | None, tube: TubeMetrics | None) -> RecordingMetrics:
    return RecordingMetrics(
        robot_ids=('a', 'b', 'c'),
        frames=10,
        complete_frames=7,
        coverage=(),
        gaps=(Gap('c', 0.5, 0.9),),
        pairs=PAIRS if collision else UNCOUNTED,
        closest=PAIRS[0],
        collision_distance_m=collision,
        collision_frames=3 if collision else None,
        tube=tube,
        source={'kind': 'synthetic'},
        inputs=(InputFile('run.bag', 12, 'ab' * 32),),
        options={'max_gap': '3periods'},
        scene='s' if tube else None,
        planned=False,
        vtube_version='0',
        provenance={},
    )


def test_collisions_counted_or_not() -> None:
    counted = metrics(0.2, None)
    assert counted.robots == 3 and counted.colliding_pairs == (('a', 'b'),) and counted.collision_pairs == 1
    free = metrics(None, None)
    assert free.colliding_pairs is None and free.collision_pairs is None
    data = free.to_json()
    assert data['collision_pairs'] is None and data['min_distance_pair'] == ['a', 'b']
    assert data['pairs_without_common_frames'] == [['a', 'c']] and data['gaps'] == [
        {'robot': 'c', 'start_s': 0.5, 'end_s': 0.9}
    ]
    assert data['inputs'] == [{'path': 'run.bag', 'bytes': 12, 'sha256': 'ab' * 32}] and 'passage' not in data


def test_the_tube_s_keys_and_strict_json() -> None:
    tube = TubeMetrics(PASSAGE, 4, 1, math.inf, 1.4, 0.6, math.nan, TrackingErrors(0.01, 0.02, 0.3, 0.5))
    data = metrics(0.2, tube).to_json()
    assert json.loads(json.dumps(data, allow_nan=False)) == data  # strict: no NaN or Infinity
    assert data['passing_time_s'] == 12.0 and data['completed'] and data['robots_passed'] == 3
    assert data['max_outside_m'] is None and data['extent_at_narrowing_m'] is None  # not finite -> None
    assert data['speed_tracking_max_mps'] == 0.02 and data['density_tracking_mean_per_m2'] == 0.3
    assert data['passage']['first_entry_s'] == 1.0 and data['scene'] == 's' and data['plan'] is False
    untracked = TubeMetrics(PASSAGE, 0, 0, 0.0, 1.4, None, None, None).to_json()
    assert 'speed_tracking_mean_mps' not in untracked and untracked['tube_violation_steps'] == 0
    assert data['tube_violation_body_radius_m'] == 0.0 and tube.violations_counted() == 'the centre'
    body = TubeMetrics(PASSAGE, 0, 0, 0.0, 1.4, None, None, None, body_radius_m=0.055)
    assert body.to_json()['tube_violation_body_radius_m'] == 0.055
    assert body.violations_counted() == 'the body (radius 0.055 m)'


def test_failures_are_collisions_and_from_a_recorded_start_robots_that_did_not_pass() -> None:
    """A passage inferred from the data is not judged; one timed from the flight's own start is."""
    from dataclasses import replace

    from robotarium_exp.analysis.passage import INFERRED_START

    recorded = replace(PASSAGE, never_inside=('c',), not_exited=('b',), start='start recorded by the flight')
    tube = TubeMetrics(recorded, 0, 0, 0.0, 1.4, None, None, None)
    assert metrics(None, tube).failures() == ('robots c never entered the tube', 'robots b never passed the exit')
    inferred = TubeMetrics(replace(recorded, start=INFERRED_START), 0, 0, 0.0, 1.4, None, None, None)
    assert metrics(None, inferred).failures() == ()
    assert metrics(0.2, None).failures() == ('1 robot pairs came closer than 0.200 m',)
    assert metrics(None, TubeMetrics(PASSAGE, 0, 0, 0.0, 1.4, None, None, None)).failures() == ()


def test_bodies_on_a_wall_fail_a_recording_as_every_verdict_on_a_robotarium_run() -> None:
    """Issue 49: the demo and `vtube analyze` judge a flight's bodies on the walls as `robotarium run` and the check
    do (`robotarium_exp.verifier.wall_failure`); centres over a wall of data of unknown robots are not judged."""
    on_wall = TubeMetrics(PASSAGE, 33, 1, 0.012, 1.4, None, None, None, body_radius_m=0.055)
    assert metrics(None, on_wall).failures() == (
        'robot bodies were on the tube walls in 33 robot-steps (1 robots, up to 0.012 m over)',
    )
    centres = TubeMetrics(PASSAGE, 33, 1, 0.012, 1.4, None, None, None)
    assert metrics(None, centres).failures() == ()
