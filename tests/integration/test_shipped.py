"""The initializer's durations shipped for the shipped scenes' formations (`submission.shipped`): current,
complete, and what the initializer gives when run again (oracle: a fresh run of V2's initializer for two seeds of a
six-robot formation). Their keys against the committed files': ``tests/unit/submission/test_shipped.py``.
"""

from __future__ import annotations

import json

import pytest

from robotarium_exp.initializer import initializer_durations
from submission.declaration import FULL_BUILD_INITIALIZER_SEEDS
from submission.reuse import SHIPPED, shipped_durations
from submission.shipped import shipped_formations, versions

TABLE = json.loads(SHIPPED.read_text(encoding='utf-8'))
CURRENT = TABLE['versions'] == versions()
STALE = 'the shipped durations are stale or incomplete: run `python -m submission.shipped` (about an hour)'


@pytest.fixture(scope='module')
def formations():
    return shipped_formations()


@pytest.mark.skipif(not CURRENT, reason=f'the table was made with {TABLE["versions"]}, not these versions')
def test_every_shipped_scene_finds_all_its_seeds_in_the_table(formations) -> None:
    table = shipped_durations()
    assert {name for scenes, _ in formations.values() for name in scenes} >= {
        'robotarium_curve',
        'robotarium_trapezoid',
        'robotarium_curve_20',
        'robotarium_trapezoid_20',
    }
    for key, (scenes, _) in formations.items():
        assert key in table, f'{scenes}: {STALE}'
        assert set(table[key]) == set(range(FULL_BUILD_INITIALIZER_SEEDS)), f'{scenes}: {STALE}'


@pytest.mark.skipif(not CURRENT, reason=f'the table was made with {TABLE["versions"]}, not these versions')
def test_a_shipped_duration_is_what_the_initializer_gives_again(formations) -> None:
    key, (_, ic) = next((key, entry) for key, entry in formations.items() if 'robotarium_curve' in entry[0])
    again = initializer_durations(ic, [0, 1], workers=2)
    assert again.durations_s == (shipped_durations()[key][0], shipped_durations()[key][1])
