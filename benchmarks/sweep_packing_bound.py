"""How many robots can start in a tube at all: Oler's bound, against the sweep's refusals (``docs/sweep/README.md``).

    python -m benchmarks.sweep_packing_bound SCENE [SCENE ...]

A SCENE may be a map file (``docs/maps/robotarium_gate.toml``): its tube is generated first, as the sweep does.

A start formation's robots stand at least the initializer's spacing d = 0.4 m apart, `WALL_CLEARANCE_M` from the
walls (or from their lines continued behind the entrance, where the entry queue stands), inside the box the
testbed initializes robots in, and before the tube's first narrowing (``docs/theory.md`` §12). Every such centre
lies in the convex hull K of that region, and Oler's inequality (N. Oler, *An inequality in the geometry of
numbers*, Acta Math. 105, 1961) bounds any set of points at least d apart in a convex K:

    N <= (2 / sqrt 3) A(K) / d^2 + P(K) / (2 d) + 1

A refusal at N above the bound is a physical impossibility under these rules, whatever the formation's layout;
one at or below it is the design's rows (rows across the tube) refusing what another packing might hold.
"""

from __future__ import annotations

import argparse
import math
import tempfile
from pathlib import Path

import numpy as np
from scipy.spatial import ConvexHull

from robotarium_exp.design import WALL_CLEARANCE_M, first_narrowing
from robotarium_exp.scene import load_scene
from robotarium_exp.spec import ROBOTARIUM
from submission.sweep import flown_scene

BEHIND_M = 3.0
"""How far behind the entrance the region is sampled (the box is 2.75 m long)."""


def packing_bound(scene_name: str) -> tuple[float, float, float, int]:
    """(the region's end l, the hull's area m^2 and perimeter m, Oler's bound on N) for a scene's tube."""
    tube = load_scene(scene_name).tube
    narrowing = first_narrowing(tube)
    end = narrowing.start_m if narrowing is not None else tube.length_m
    l_m = np.linspace(-BEHIND_M, end, 6001)
    room = np.maximum(tube.half_width(np.maximum(l_m, 0.0)) - WALL_CLEARANCE_M, 0.0)
    across = np.linspace(-1.0, 1.0, 81)
    offsets = across[None, :, None] * room[:, None, None] * tube.normal(l_m)[:, None, :]
    points = (tube.center_at(l_m)[:, None, :] + offsets).reshape(-1, 2)
    points = points[np.all(np.abs(points) <= np.array(ROBOTARIUM.ic_box_m), axis=1)]
    hull = ConvexHull(points)
    d = ROBOTARIUM.ic_spacing_m
    bound = math.floor(2.0 / math.sqrt(3.0) * hull.volume / d**2 + hull.area / (2.0 * d) + 1.0)
    return end, float(hull.volume), float(hull.area), bound


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('scenes', nargs='+', help='shipped names, .toml files or map files')
    for name in parser.parse_args().scenes:
        with tempfile.TemporaryDirectory(prefix='vtube-packing-') as folder:
            end, area, perimeter, bound = packing_bound(flown_scene(name, Path(folder)))
        print(
            f'{name}: region up to l = {end:.2f} m, hull {area:.2f} m^2, perimeter {perimeter:.2f} m: at most {bound} '
            'robots can start'
        )


if __name__ == '__main__':
    main()
