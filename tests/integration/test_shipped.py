"""The initializer's durations shipped for the shipped scenes' formations (`submission.shipped`): current, complete,
keyed as a build keys them, and what the initializer gives when run again.

Oracles: the keys of the committed submissions' own initial conditions (read from their ``DATA``, not from the
scenes), and a fresh run of V2's initializer for two seeds of a six-robot formation.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from robotarium_exp.initializer import INITIALIZATION_LIMIT, initializer_durations
from submission.check import file_flight_data
from submission.declaration import FULL_BUILD_INITIALIZER_SEEDS
from submission.reuse import SHIPPED, initializer_key, shipped_durations
from submission.shipped import shipped_formations, versions

ROOT = Path(__file__).resolve().parents[2]
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


def test_the_formations_are_keyed_as_the_build_keys_the_files_it_made(formations) -> None:
    """The committed files' initial conditions (what a check reads) give the keys the scenes give."""
    for stem in ('vtube_robotarium_curve', 'vtube_robotarium_trapezoid_20'):
        data = file_flight_data((ROOT / 'submissions' / f'{stem}.py').read_text(encoding='utf-8'))
        key = initializer_key(data.initial_conditions, INITIALIZATION_LIMIT)
        assert stem.removeprefix('vtube_') in formations[key][0]


@pytest.mark.skipif(not CURRENT, reason=f'the table was made with {TABLE["versions"]}, not these versions')
def test_a_shipped_duration_is_what_the_initializer_gives_again(formations) -> None:
    key, (_, ic) = next((key, entry) for key, entry in formations.items() if 'robotarium_curve' in entry[0])
    again = initializer_durations(ic, [0, 1], workers=2)
    assert again.durations_s == (shipped_durations()[key][0], shipped_durations()[key][1])
