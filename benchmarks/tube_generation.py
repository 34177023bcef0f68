"""Tubes generated from seeded random maps: how many are certified, why the others are refused, how long a map
takes, and whether every certified tube misses its obstacles (independently, at 1 cm) and plans certified.

    python -m benchmarks.tube_generation [--seeds 100] [--families forest,blocks,bottleneck] [--workers 2]
        [--no-plan] [--list]

Per family (`vtube_planning.geometry.from_maps.maps`, 80 m x 40 m at 0.1 m): maps; certified tubes; refusals by
reason (no passage with the room, a corner too tight for the 4 m radius, other); the generation time per map
(median and largest, seconds of one process; ``benchmarks/tube_generation_speed.py`` times generation alone, and
against another checkout); certified tubes the independent check finds within the 0.3 m margin
of an obstacle (``tests/support/tube_clearance.py``: 1 cm along, 101 points across; must be 0); and certified tubes
whose plan (Table 1's swarm, the convex planner) is certified. ``--list`` also prints each family's certified seeds
(what a campaign's ``map_seed`` axis lists: ``docs/maps_study/campaign.toml``) and every refusal with its reason.
"""

from __future__ import annotations

import argparse
import collections
import statistics
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor


def one_map(family: str, seed: int, plan: bool) -> dict[str, object]:
    """Generate the map's tube, check it, plan it."""
    from tests.support.tube_clearance import closest_approach
    from vtube_planning.geometry.from_maps.generate import TubeGenerationError, generate_tube
    from vtube_planning.geometry.from_maps.maps import LIMITS, random_map
    from vtube_planning.params import PlanningOptions, SwarmParams
    from vtube_planning.planning.planner import plan_convex

    spec = random_map(family, seed)
    started = time.perf_counter()
    try:
        made = generate_tube(spec)
    except TubeGenerationError as err:
        text = str(err)
        reason = (
            'no passage'
            if text.startswith('no passage')
            else 'tight corner'
            if 'cannot be rounded' in text
            else 'other'
        )
        return {'family': family, 'outcome': reason, 'seconds': time.perf_counter() - started, 'text': text}
    seconds = time.perf_counter() - started
    clear = closest_approach(made.tube, spec.obstacles) >= LIMITS['margin_m'] - 1e-9
    certified = plan_convex(made.tube, SwarmParams(), PlanningOptions()).is_certified() if plan else None
    return {'family': family, 'outcome': 'certified', 'seconds': seconds, 'clear': clear, 'plan': certified}


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seeds', type=int, default=100)
    parser.add_argument('--families', default='forest,blocks,bottleneck')
    parser.add_argument('--workers', type=int, default=2)
    parser.add_argument('--no-plan', action='store_true')
    parser.add_argument('--list', action='store_true', help="each family's certified seeds, and every refusal")
    args = parser.parse_args(argv)
    families = args.families.split(',')
    jobs = [(f, s, not args.no_plan) for f in families for s in range(args.seeds)]
    with ProcessPoolExecutor(args.workers) as pool:
        rows = list(pool.map(one_map, *zip(*jobs, strict=True)))
    print(
        '| family | maps | certified | no passage | tight corner | other | seconds per map, median (max) '
        '| certified within the margin at 1 cm | plans certified |'
    )
    print('|---|---|---|---|---|---|---|---|---|')
    for family in families:
        mine = [r for r in rows if r['family'] == family]
        count = collections.Counter(r['outcome'] for r in mine)
        seconds = [float(r['seconds']) for r in mine]  # type: ignore[arg-type]
        made = [r for r in mine if r['outcome'] == 'certified']
        plans = 'not run' if args.no_plan else f'{sum(bool(r["plan"]) for r in made)} of {len(made)}'
        print(
            f'| {family} | {len(mine)} | {count["certified"]} | {count["no passage"]} | {count["tight corner"]} | '
            f'{count["other"]} | {statistics.median(seconds):.2f} ({max(seconds):.2f}) | '
            f'{sum(not r["clear"] for r in made)} | {plans} |'
        )
    for (family, seed, _), r in zip(jobs, rows, strict=True):
        if r['outcome'] == 'other' or args.list and r['outcome'] != 'certified':
            print(f'{family} seed {seed} refused ({r["outcome"]}): {r["text"]}')
    if args.list:
        for family in families:
            seeds = [s for (f, s, _), r in zip(jobs, rows, strict=True) if f == family and r['outcome'] == 'certified']
            print(f'{family} certified seeds ({len(seeds)}): {seeds}')


if __name__ == '__main__':
    main()
