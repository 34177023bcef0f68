"""How many robots can start in a tube at all: Oler's bound, against the sweep's refusals (``docs/sweep/README.md``).

    python -m benchmarks.sweep_packing_bound SCENE [SCENE ...]

A SCENE may be a map file (``docs/maps/robotarium_gate.toml``): its tube is generated first, as the sweep does.

The bound is `robotarium_exp.packing.packing_bound`: Oler's inequality on the convex hull of the start region
(robots 0.4 m apart, 0.1 m from the walls or their lines continued behind the entrance, inside the box the testbed
initializes robots in, before the first narrowing). A refusal at N above it is a physical impossibility under these
rules, whatever the layout (the fit verdict says so); at or below it, `robotarium_exp.packing.packed_poses` tries a
packing in no rows, and the command prints the most robots it packs, and the fewest robots above them that
`robotarium_exp.packing_proof.refuted` proves do not fit (15 s to 6 minutes each; the sweep's verdict asks the same).
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

from robotarium_exp.packing import packed_poses, packing_bound
from robotarium_exp.packing_proof import refuted
from robotarium_exp.scene import load_scene
from submission.sweep import flown_scene


def packing_counts(scene_name: str) -> tuple[int, int, int]:
    """(Oler's bound, the most robots `refuted` leaves possible, the most `packed_poses` places, counting up from 1)
    for a scene's tube."""
    tube = load_scene(scene_name).tube
    bound = packing_bound(tube)
    packed = 0
    while packed < bound and packed_poses(tube, packed + 1) is not None:
        packed += 1
    proved = next((n - 1 for n in range(packed + 1, bound + 1) if refuted(tube, n)), bound)
    return bound, proved, packed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('scenes', nargs='+', help='shipped names, .toml files or map files')
    for name in parser.parse_args().scenes:
        with tempfile.TemporaryDirectory(prefix='vtube-packing-') as folder:
            bound, proved, packed = packing_counts(flown_scene(name, Path(folder)))
        print(f'{name}: at most {bound} robots can start (Oler), at most {proved} (proved), {packed} packed')


if __name__ == '__main__':
    main()
