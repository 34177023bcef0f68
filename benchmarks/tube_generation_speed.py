"""Seconds per map of tube generation, in this process, per family: the median, the largest and the slowest seeds;
with ``--against DIR``, the same maps generated in turn by another checkout of the package too (a ``git worktree``
of an older commit, say), the ratio of the times, and the maps whose tubes or refusals differ to the bit.

    python -m benchmarks.tube_generation_speed [--seeds 100] [--families forest,blocks,bottleneck] [--against DIR]

Each map is generated once by each (this checkout first, then the other), so a load that comes and goes slows
both alike and the ratio holds on a busy machine; the absolute seconds do not (run it on an idle machine for
those). A tube is compared by its centre curve's and width's pieces and its start (``repr``: every bit of every
number), a refusal by its message.
"""

from __future__ import annotations

import argparse
import importlib
import statistics
import sys
import time
from collections.abc import Callable, Sequence

Generator = Callable[[str, int], str]
"""(family, seed) -> what was made, as text (the tube to the bit, or the refusal)."""


def generator(root: str | None) -> Generator:
    """Generation by the checkout at ``root`` (None: this one), its modules imported afresh and then put aside."""
    ours = {name: module for name, module in sys.modules.items() if name.partition('.')[0] == 'vtube_planning'}
    if root is not None:
        for name in ours:
            del sys.modules[name]
        sys.path.insert(0, root)
    try:
        generate = importlib.import_module('vtube_planning.geometry.from_maps.generate')
        maps = importlib.import_module('vtube_planning.geometry.from_maps.maps')
    finally:
        if root is not None:
            sys.path.remove(root)
            for name in [name for name in sys.modules if name.partition('.')[0] == 'vtube_planning']:
                del sys.modules[name]
            sys.modules.update(ours)

    def made(family: str, seed: int) -> str:
        try:
            tube = generate.generate_tube(maps.random_map(family, seed)).tube
        except generate.TubeGenerationError as err:
            return f'refused: {err}'
        center, width = tube.center, tube.width
        return repr((center.start_xy_m, center.heading_rad, center.pieces, width.start_m, width.parts))

    return made


def timed(made: Generator, family: str, seed: int) -> tuple[float, str]:
    started = time.perf_counter()
    text = made(family, seed)
    return time.perf_counter() - started, text


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seeds', type=int, default=100)
    parser.add_argument('--families', default='forest,blocks,bottleneck')
    parser.add_argument('--against', default=None, help='the root of another checkout (holding vtube_planning/)')
    args = parser.parse_args(argv)
    this, other = generator(None), (generator(args.against) if args.against else None)
    print(
        '| family | maps | seconds per map, median (max) | slowest seeds |'
        + (' other checkout | ratio | differ |' if other else '')
    )
    print('|---|---|---|---|' + ('---|---|---|' if other else ''))
    for family in args.families.split(','):
        ours, theirs, differ = [], [], []
        for seed in range(args.seeds):
            seconds, text = timed(this, family, seed)
            ours.append(seconds)
            if other is not None:
                seconds, their_text = timed(other, family, seed)
                theirs.append(seconds)
                differ += [seed] if their_text != text else []
        slowest = sorted(range(args.seeds), key=lambda s: -ours[s])[:3]
        row = f'| {family} | {args.seeds} | {statistics.median(ours):.3f} ({max(ours):.3f}) | {slowest} |'
        if other is not None:
            row += (
                f' {statistics.median(theirs):.3f} ({max(theirs):.3f}) | {sum(ours) / sum(theirs):.2f} | '
                f'{len(differ)}{f" (seeds {differ})" if differ else ""} |'
            )
        print(row)


if __name__ == '__main__':
    main()
