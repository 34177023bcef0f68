"""Why the plan passes later than the unplanned swarm on generated maps: where (p4) holds its speed down.

    python -m benchmarks.maps_curvature [docs/maps_study]

For each map of a finished campaign over random maps (``vtube campaign run docs/maps_study/campaign.toml``): the
plan's share of grid points where the curvature limit sqrt(a_n r_t) of (p4) binds (its speed at the limit), and
the map's mean passing time with planning less without (over its seeds). Prints their correlation over maps, and
the mean difference on the maps where (p4) binds on more or less than a fifth of the tube.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from vtube_planning.planning.planner import plan_convex
from vtube_planning.studies.campaign_store import read_results
from vtube_planning.studies.study import Point


def main(argv: list[str] | None = None) -> None:
    folder = Path((argv if argv is not None else sys.argv[1:] or ['docs/maps_study'])[0])
    _, rows, _ = read_results(folder)
    maps = sorted({(r['scene'], r['map'], r['map_seed'], r['map_clutter'], r['map_width_m']) for r in rows})
    shares, differences = [], []
    for scene, family, seed, clutter, width in maps:
        sel = [r for r in rows if (r['scene'], r['map'], r['map_seed']) == (scene, family, seed)]
        mean = {m: np.mean([r['passing_time_s'] for r in sel if r['mode'] == m]) for m in ('planning', 'no planning')}
        flown = Point(scene, map=family, map_seed=seed, map_clutter=clutter, map_width_m=width).load_scene()
        plan = plan_convex(flown.tube, flown.swarm, flown.planning)
        shares.append(float(np.mean(plan.speed_mps >= plan.speed_limit_mps - 1e-6)))
        differences.append(float(mean['planning'] - mean['no planning']))
    share, difference = np.array(shares), np.array(differences)
    print(f'{len(maps)} maps; correlation of the (p4)-bound share with planning - no planning [s]: '
          f'{np.corrcoef(share, difference)[0, 1]:.2f}')  # fmt: skip
    for name, chosen in (('more than', share > 0.2), ('at most', share <= 0.2)):
        if chosen.any():
            print(f'(p4) binds on {name} a fifth of the tube: {chosen.sum()} maps, planning - no planning '
                  f'{difference[chosen].mean():+.2f} s on average; planning faster on {(difference[chosen] < 0).sum()}')  # fmt: skip


if __name__ == '__main__':
    main()
