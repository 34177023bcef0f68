"""Replay real Robotarium runs through the testbed models: how far off is each after 1, 10 and 100 iterations?

    VTUBE_REALDATA=../shared/realdata python -m benchmarks.testbed_replay [--more DIR] [--every 25]

For every run (`benchmarks.testbed_runs`), every ``--every`` iterations k: start from the recorded pose k, feed
the recorded commands k, k+1, ... (clipped per wheel, as the testbed does) through the model's command path
(`robotarium_exp.rps.testbed_model.Testbed`: delay, lag, gains, bias; no pose noise, gains at their means),
integrate as the simulator does (forward Euler at 0.033 s), and compare the position after h iterations with the
recorded pose k+h. The model's history is warmed up with the commands before k (from the start of the run, as on
the testbed), so a delayed model starts with the commands already on their way. Windows whose recorded poses jump
(a step over 2 cm) are left out. Printed: median and p90 of the error, in mm, per model and horizon.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np

from benchmarks.testbed_runs import DT, Run, clipped, default_files, load_runs
from robotarium_exp.rps.testbed_model import Testbed, TestbedModel, testbed_model

HORIZONS = (1, 10, 100)
WARM_UP = 40
"""Commands fed before the start pose (more than any delay plus five lag times of the models replayed)."""


def without_noise(model: TestbedModel) -> TestbedModel:
    """``model``'s command path at its mean gains and bias, without stalls, poses untouched."""
    return replace(
        model,
        speed_gain_sd=0.0,
        turn_gain_sd=0.0,
        turn_bias_sd_rad_s=0.0,
        noise_along_m=0.0,
        noise_across_m=0.0,
        noise_heading_rad=0.0,
        heading_quantum_rad=0.0,
        stale_rate=0.0,
        stale_rate_still=0.0,
        stall_rate=0.0,
    )


def replay(run: Run, model: TestbedModel, every: int) -> np.ndarray:
    """Position errors (starts, horizons) in m of ``model`` replaying ``run`` from every ``every``-th pose."""
    u = clipped(run.commands)
    longest = max(HORIZONS)
    starts = np.arange(WARM_UP, len(u) - longest, every)
    if starts.size == 0:
        return np.empty((0, len(HORIZONS)))
    n = u.shape[2]
    testbed = Testbed(without_noise(model), starts.size * n, DT)
    for back in range(WARM_UP, 0, -1):
        testbed.actuate(u[starts - back].transpose(1, 0, 2).reshape(2, -1))
    pose = run.poses[starts].transpose(1, 0, 2).reshape(3, -1).copy()
    errors = []
    for h in range(1, longest + 1):
        moving = testbed.actuate(u[starts + h - 1].transpose(1, 0, 2).reshape(2, -1))
        pose[0] += DT * moving[0] * np.cos(pose[2])
        pose[1] += DT * moving[0] * np.sin(pose[2])
        pose[2] += DT * moving[1]
        if h in HORIZONS:
            truth = run.poses[starts + h].transpose(1, 0, 2).reshape(3, -1)
            errors.append(np.hypot(pose[0] - truth[0], pose[1] - truth[1]))
    step = np.hypot(*np.diff(run.poses[:, :2], axis=0).transpose(1, 0, 2))  # (T-1, N)
    jumped = np.array([(step[k : k + longest] > 0.02).any(axis=0) for k in starts]).reshape(-1)
    return np.asarray(np.array(errors).T[~jumped])


def table(runs: list[Run], names: list[str], every: int) -> list[str]:
    """The printed table: per model, median and p90 of the position error at each horizon (mm)."""
    lines = ['model       ' + ''.join(f'   after {h:>3d} it (median / p90)' for h in HORIZONS)]
    for name in names:
        errors = np.vstack([replay(run, testbed_model(name), every) for run in runs])
        cells = [
            f'{1000 * np.median(errors[:, j]):12.1f} / {1000 * np.percentile(errors[:, j], 90):6.1f} mm'
            for j in range(len(HORIZONS))
        ]
        lines.append(f'{name:10s}  ' + ''.join(f'{c:>30s}' for c in cells) + f'   ({len(errors)} windows)')
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog='python -m benchmarks.testbed_replay', description=__doc__)
    parser.add_argument('--more', type=Path, default=None, help='a folder of further .mat runs (fetched, in /tmp)')
    parser.add_argument('--every', type=int, default=25, help='iterations between two replay starts (default 25)')
    parser.add_argument('--models', default='ideal,fitted', help='comma-separated model names (default ideal,fitted)')
    args = parser.parse_args(argv)
    runs = load_runs(default_files(args.more))
    if not runs:
        print('no runs: set VTUBE_REALDATA to the real recordings (robotarium-cbf4, robotarium-lines3) or give --more')
        return 2
    print(f'{len(runs)} runs; replays start every {args.every} iterations')
    print('\n'.join(table(runs, args.models.split(','), args.every)))
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
