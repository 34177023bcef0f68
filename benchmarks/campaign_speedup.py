"""How much faster a campaign runs on more local processes, and whether the rows stay the same.

    python -m benchmarks.campaign_speedup [--workers 2] [--seeds 5] [--scenes A,B,C,D]

The reduced study (``vtube study``'s grid: each scene with and without planning over the seeds) runs into two
fresh folders in this process, first with one worker (the runs in this process, one after another), then with
``--workers`` processes; prints both wall times, their ratio, and whether every row but the wall time is equal.
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path
from typing import Any

from vtube_planning.studies.campaign import Campaign
from vtube_planning.studies.campaign_runner import run_campaign
from vtube_planning.studies.study import MODES


def comparable(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    return [
        {k: None if isinstance(v, float) and math.isnan(v) else v for k, v in row.items() if k != 'wall_s'}
        for row in rows
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--workers', type=int, default=2)
    parser.add_argument('--seeds', type=int, default=5)
    parser.add_argument('--scenes', default='A,B,C,D')
    args = parser.parse_args()
    grid = {'scene': tuple(args.scenes.split(',')), 'mode': MODES, 'seed': tuple(range(args.seeds))}
    campaign = Campaign((grid,), name='reduced study')
    seconds, rows = {}, {}
    with tempfile.TemporaryDirectory() as folder:
        for workers in (1, args.workers):
            started = time.perf_counter()
            outcome = run_campaign(campaign, Path(folder) / str(workers), workers=workers, progress=False)
            seconds[workers] = time.perf_counter() - started
            rows[workers] = comparable(outcome.rows)
    print(f'{len(rows[1])} runs ({campaign.name}: scenes {args.scenes}, {len(MODES)} modes, {args.seeds} seeds)')
    print(
        f'| workers | wall time [s] |\n|---|---|\n| 1 | {seconds[1]:.1f} |\n| {args.workers} | {seconds[args.workers]:.1f} |'
    )
    print(f'speed-up: {seconds[1] / seconds[args.workers]:.2f}x; same rows: {rows[1] == rows[args.workers]}')


if __name__ == '__main__':
    main()
