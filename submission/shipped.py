"""The initializer's durations for the formations of the shipped Robotarium scenes, shipped with the package.

A full build runs V2's initializer alone over 200 seeds for the file's initial conditions (`submission.declaration`):
about 9 CPU minutes for six robots, 100 for twenty, most of it in cvxopt's barrier QP, which stays (the testbed's
answers, ``docs/robotarium.md`` §2.6). The shipped scenes' formations are the same for every researcher, so their
durations ship in `submission.reuse.SHIPPED`, under the same key as the user's cache (`submission.reuse.initializer_key`:
the initial conditions as the file embeds them, the step limit, the initializer's sources and the versions of Python,
numpy, scipy and cvxopt). A build whose key matches takes them from there; any other key (an own formation, a changed
simulator, other versions) runs the seeds as before.

    python -m submission.shipped

writes the table again: for each Robotarium scene shipped in ``robotarium_exp.scenes``, the durations of its
formation over `FULL_BUILD_INITIALIZER_SEEDS` seeds (taken from the user's cache where they are there, run and added
to it where not: about an hour on two cores for the twenty-robot formation). ``tests/integration/test_shipped.py``
checks that every shipped scene's key is in the table (when the versions are those it was made with) and that a seed
run again gives the stored duration.
"""

from __future__ import annotations

import json
import platform
import sys
from importlib import metadata, resources

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.experiment import ExperimentConfig, flight_data
from robotarium_exp.initializer import INITIALIZATION_LIMIT
from robotarium_exp.scene import load_scene
from submission.declaration import FULL_BUILD_INITIALIZER_SEEDS
from submission.reuse import SHIPPED, VERSIONED, cached_initializer_durations, initializer_key
from vtube_planning.files import write_atomically

SCENE_PACKAGE = 'robotarium_exp.scenes'


def versions() -> dict[str, str]:
    """The versions the key depends on, as the table records them (to tell a stale table from other versions)."""
    return {'python': platform.python_version(), **{name: metadata.version(name) for name in VERSIONED}}


def shipped_formations() -> dict[str, tuple[list[str], NDArray[np.float64]]]:
    """Each shipped Robotarium scene's key: the scenes of that formation and its initial conditions (3xN), as the
    built file embeds them (rounded: `robotarium_exp.flight_data`)."""
    found: dict[str, tuple[list[str], NDArray[np.float64]]] = {}
    for file in sorted(resources.files(SCENE_PACKAGE).iterdir(), key=lambda f: f.name):
        if file.name.endswith('.toml'):
            name = file.name.removesuffix('.toml')
            ic = flight_data(load_scene(name), None, ExperimentConfig(planning=False)).initial_conditions
            scenes, _ = found.setdefault(initializer_key(ic, INITIALIZATION_LIMIT), ([], ic))
            scenes.append(name)
    return found


def main() -> None:
    """Write `submission.reuse.SHIPPED` for the shipped scenes' formations (module doc)."""
    formations = []
    for key, (scenes, ic) in shipped_formations().items():
        print(f'{", ".join(scenes)}: {ic.shape[1]} robots, {FULL_BUILD_INITIALIZER_SEEDS} seeds', file=sys.stderr)
        sample = cached_initializer_durations(ic, range(FULL_BUILD_INITIALIZER_SEEDS))
        durations = iter(sample.durations_s)
        by_seed = {
            str(seed): None if seed in sample.stuck_seeds else next(durations)
            for seed in range(FULL_BUILD_INITIALIZER_SEEDS)
        }
        formations.append({'scenes': scenes, 'key': key, 'durations_s': by_seed})
    table = {'made_by': 'python -m submission.shipped', 'versions': versions(), 'formations': formations}
    write_atomically(SHIPPED, json.dumps(table, indent=1) + '\n')
    print(f'wrote {SHIPPED}', file=sys.stderr)


if __name__ == '__main__':
    main()
