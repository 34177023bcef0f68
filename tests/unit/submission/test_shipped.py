"""The shipped scenes' formations and the table `submission.shipped` writes for them.

Oracles: the keys of the committed submissions' own initial conditions (read from their ``DATA``, not from the
scenes), and `submission.reuse.shipped_durations` reading the written table back. The table itself against the
initializer run again: ``tests/integration/test_shipped.py``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from robotarium_exp.initializer import INITIALIZATION_LIMIT, InitializerSample
from submission import reuse, shipped
from submission.check import file_flight_data
from submission.declaration import FULL_BUILD_INITIALIZER_SEEDS

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope='module')
def formations():
    return shipped.shipped_formations()


def test_the_shipped_scenes_make_three_formations_keyed_as_the_build_keys_its_files(formations) -> None:
    """Every Robotarium scene shipped is there; the two twenty-robot scenes start from the same poses; the key of
    each committed file's initial conditions (what its check computes) names its scene."""
    by_scene = {name: key for key, (scenes, _) in formations.items() for name in scenes}
    assert set(by_scene) == {
        'robotarium_curve',
        'robotarium_trapezoid',
        'robotarium_curve_20',
        'robotarium_trapezoid_20',
    }
    assert len(formations) == 3 and by_scene['robotarium_curve_20'] == by_scene['robotarium_trapezoid_20']
    for scene, key in by_scene.items():
        data = file_flight_data((ROOT / 'submissions' / f'vtube_{scene}.py').read_text(encoding='utf-8'))
        assert reuse.initializer_key(data.initial_conditions, INITIALIZATION_LIMIT) == key
        assert np.array_equal(formations[key][1], data.initial_conditions)


def test_the_table_written_reads_back_as_the_durations_it_was_given(tmp_path, monkeypatch, formations) -> None:
    """main writes each formation's seeds (a stuck one as null) with the versions; the lookup reads them back."""
    table = tmp_path / 'shipped.json'
    monkeypatch.setattr(shipped, 'SHIPPED', table)
    monkeypatch.setattr(reuse, 'SHIPPED', table)
    monkeypatch.setattr(shipped, 'shipped_formations', lambda: formations)
    made = {key: k + 1.0 for k, key in enumerate(formations)}

    def durations(ic, seeds):
        key = reuse.initializer_key(ic, INITIALIZATION_LIMIT)
        return InitializerSample(tuple(made[key] + seed for seed in list(seeds)[1:]), (0,))  # seed 0 stuck

    monkeypatch.setattr(shipped, 'cached_initializer_durations', durations)
    shipped.main()
    written = json.loads(table.read_text(encoding='utf-8'))
    assert written['versions'] == shipped.versions() and written['versions']['cvxopt']
    back = reuse.shipped_durations()
    assert set(back) == set(formations)
    for key, seeds in back.items():
        assert seeds[0] is None and len(seeds) == FULL_BUILD_INITIALIZER_SEEDS
        assert all(seeds[seed] == made[key] + seed for seed in range(1, FULL_BUILD_INITIALIZER_SEEDS))
