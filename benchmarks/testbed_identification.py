"""Fit the testbed model (`robotarium_exp.rps.testbed_model`) from real Robotarium runs and print the numbers.

    VTUBE_REALDATA=../shared/realdata python -m benchmarks.testbed_identification [--more DIR]

The runs: ``robotarium-cbf4`` and ``robotarium-lines3`` beside the project (``$VTUBE_REALDATA`` or
``../shared/realdata``) and, with ``--more``, the ``.mat`` files of a folder, e.g. the runs of yemam3/robustCBFs-GP's
history (commits 84641ed, 1144a4b, 151333e; ``saved_data/**/robotarium*_data.mat``) copied to /tmp with the
``fetch`` tool and ``git show`` (never into the project). `benchmarks.testbed_runs` reads them.

What is measured, on the per-wheel clipped commands u and the velocities the poses show, iteration k to k+1
(v along the heading, omega from the heading), where neither pose is stale nor part of a jump:
* delay and lag, per channel: the candidate delays 0, 0.5, ..., 10 iterations and lags 0, 0.02, ..., 0.5 s, each
  turned into the model's response to u (`response`), the gain (and the turn-rate bias) by least squares; the
  pair of least squared residual wins, pooled over the runs and per run (median, p10-p90). The centroid of the
  response is delay + lag / period;
* gains and bias per robot and run at the pooled delay and lag (median, robust sd over robots and runs);
* pose noise: the residual of each pose from a quadratic through its 9 neighbours (k-4..k+4), along and across the
  heading and of the heading, robust sd (1.4826 MAD) corrected for the fit's own share; the heading quantum;
* stale poses (exactly the previous pose) per iteration of a robot actually driving (at least 20 mm/s over the
  5 poses either side) and of one actually standing (below 2 mm/s), away from loop stalls;
* stalls: a driving robot's pose steps more than 2 cm (which no robot drives in 0.033 s), per 1000 robot-iterations
  of driving robots; how many periods more it drove (the step over its speed before it, robots at 50 mm/s or
  more), whether the step lies along the heading, whether the robot stays there (continuation) or comes back
  (a tracker outlier), and how many of the other robots as fast stalled in the same iteration.

Runs whose commands were scaled after they were saved are left out: yemam3/robustCBFs-GP's
``main_robotarium_3.m`` multiplies ``dxu`` by 0.8 (or 1.2) in the quadrant x < 0, y > 0 after ``data_saver.save``,
so the saved commands are not what drove the robots there (`scaled_after_saving`: the response's gain inside that
quadrant differs from outside by more than 10 %, in either channel).

Model version 1's figures (every run; stale poses by the commands: moving when any command above 5 mm/s came in
the last 10 iterations; jumps per robot-iteration) are printed beside the new ones.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.signal import lfilter

from benchmarks.testbed_runs import DT, Run, clipped, default_files, load_runs

DELAYS = np.arange(0.0, 10.01, 0.5)
LAGS_S = np.arange(0.0, 0.501, 0.02)
JUMP_M = 0.02
CLOSED_LOOP_STEPS = 900
"""Runs this long are closed loop (their commands vary); the 500-step open-loop lines hold constant commands,
which identify gains but not delays, so the per-run delays are those of the longer runs."""
STILL_MPS = 0.005
"""Version 1: a robot whose commanded speed stayed below this (and turn rate below 10 times it) over the last 10
iterations stood still."""
DRIVING_MPS = 0.02
STOPPED_MPS = 0.002
"""A robot drives (stands) when its pose moved at least (less than) this speed over the ``WINDOW`` poses either side."""
WINDOW = 5
STALL_SPEED_MPS = 0.05
"""The periods a stall lasted are measured on robots at least this fast before it."""
SCALED = 0.1
"""A run whose response gain in the quadrant x < 0, y > 0 differs by more than this share from outside it."""


def response(u: np.ndarray, delay: float, lag_s: float) -> np.ndarray:
    """The model's response (T, N) to commands ``u`` (T, N): delayed (linear between iterations), then lagged."""
    whole, frac = int(np.floor(delay)), delay - np.floor(delay)
    padded = np.vstack([np.zeros((whole + 1, u.shape[1])), u])
    delayed = (1 - frac) * padded[1 : 1 + len(u)] + frac * padded[: len(u)]
    if lag_s <= 0:
        return np.asarray(delayed)
    alpha = 1 - np.exp(-DT / lag_s)
    return np.asarray(lfilter([alpha], [1, alpha - 1], delayed, axis=0))


def measured(run: Run) -> tuple[np.ndarray, np.ndarray]:
    """Speed and turn rate from pose k to k+1 (T-1, 2, N), and where both poses are usable (T-1, N)."""
    p = run.poses
    step = np.diff(p, axis=0)
    step[:, 2] = np.angle(np.exp(1j * step[:, 2]))
    rates = np.stack([(step[:, 0] * np.cos(p[:-1, 2]) + step[:, 1] * np.sin(p[:-1, 2])) / DT, step[:, 2] / DT], axis=1)
    bad = np.all(step == 0, axis=1) | (np.hypot(step[:, 0], step[:, 1]) > JUMP_M) | (np.abs(rates[:, 1]) > 8)
    bad |= np.vstack([bad[1:], bad[-1:]]) | np.vstack([bad[:1], bad[:-1]])  # the step after a stale pose catches up
    return rates, ~bad


def fit_channel(runs: list[Run], channel: int) -> tuple[float, float, float]:
    """The (delay, lag, residual) of least squared residual over ``runs`` for ``channel`` (0: v, 1: omega)."""
    data = [(clipped(r.commands)[:-1, channel], *_rates(r, channel)) for r in runs]
    best = (np.inf, 0.0, 0.0)
    for delay in DELAYS:
        for lag in LAGS_S:
            sse = 0.0
            for u, y, ok in data:
                f = response(u, delay, lag)
                sse += sum(_gain_fit(f[:, i], y[:, i], ok[:, i], channel)[2] for i in range(u.shape[1]))
            best = min(best, (sse, float(delay), float(lag)))
    return best[1], best[2], best[0]


def _rates(run: Run, channel: int) -> tuple[np.ndarray, np.ndarray]:
    rates, ok = measured(run)
    return rates[:, channel], ok


def _gain_fit(f: np.ndarray, y: np.ndarray, ok: np.ndarray, channel: int) -> tuple[float, float, float]:
    """Gain and bias (omega only) of y ~ gain f + bias on ``ok``, and the squared residual."""
    f, y = f[ok], y[ok]
    if f.size < 20 or np.ptp(f) == 0:
        return np.nan, np.nan, 0.0
    columns = [f, np.ones_like(f)] if channel == 1 else [f]
    coef, *_ = np.linalg.lstsq(np.column_stack(columns), y, rcond=None)
    residual = y - np.column_stack(columns) @ coef
    return float(coef[0]), float(coef[1]) if channel == 1 else 0.0, float(residual @ residual)


def per_robot(runs: list[Run], channel: int, delay: float, lag: float) -> np.ndarray:
    """Gain and bias (k, 2) of every robot of every run with enough motion, at the given delay and lag."""
    out = []
    for run in runs:
        u = clipped(run.commands)[:-1, channel]
        y, ok = _rates(run, channel)
        f = response(u, delay, lag)
        for i in range(u.shape[1]):
            if np.abs(u[:, i]).max() > 0.02 and ok[:, i].sum() > 200:
                out.append(_gain_fit(f[:, i], y[:, i], ok[:, i], channel)[:2])
    return np.array(out)


def pose_noise(runs: list[Run]) -> tuple[float, float, float]:
    """Robust sd of the poses about a local quadratic (k-4..k+4): along, across the heading (m), heading (rad)."""
    offsets = np.arange(-4, 5)
    basis = np.vander(offsets, 3)
    smoother = (basis @ np.linalg.pinv(basis))[4]  # the quadratic's value at the centre, as weights of the 9 poses
    scale = np.sqrt(np.sum((np.eye(9)[4] - smoother) ** 2))  # white noise of sd s leaves a residual of sd s*scale
    along, across, heading = [], [], []
    for run in runs:
        p = run.poses.copy()
        p[:, 2] = np.unwrap(p[:, 2], axis=0)
        windows = np.stack([p[4 + o : len(p) - 4 + o] for o in offsets])  # (9, T-8, 3, N)
        residual = windows[4] - np.tensordot(smoother, windows, axes=1)
        moved = np.abs(np.diff(windows, axis=0))
        ok = np.all(moved.max(axis=2) > 0, axis=0) & np.all(np.hypot(moved[:, :, 0], moved[:, :, 1]) < JUMP_M, axis=0)
        c, s = np.cos(windows[4][:, 2]), np.sin(windows[4][:, 2])
        along.append((residual[:, 0] * c + residual[:, 1] * s)[ok])
        across.append((-residual[:, 0] * s + residual[:, 1] * c)[ok])
        heading.append(residual[:, 2][ok])
    sd_along, sd_across, sd_heading = (_robust_sd(np.concatenate(x)) / scale for x in (along, across, heading))
    return sd_along, sd_across, sd_heading


def _robust_sd(x: np.ndarray) -> float:
    return float(1.4826 * np.median(np.abs(x - np.median(x))))


def heading_quantum(runs: list[Run]) -> float:
    """The share of headings that are whole multiples of 0.001 rad."""
    th = np.concatenate([r.poses[:, 2].ravel() for r in runs])
    return float(np.mean(np.abs(th * 1000 - np.round(th * 1000)) < 1e-6))


def stale_and_jumps(runs: list[Run]) -> dict[str, float]:
    """Model version 1's measures: stale-pose rates (moving, standing still: by the commands), jumps per 1000
    robot-iterations and their median size (m)."""
    stale_moving, stale_still, jumps, sizes, total = [], [], 0, [], 0
    for run in runs:
        u = np.abs(clipped(run.commands))
        still = np.ones(u[:, 0].shape, dtype=bool)
        for back in range(10):
            still[back:] &= (u[: len(u) - back, 0] < STILL_MPS) & (u[: len(u) - back, 1] < 10 * STILL_MPS)
        step = np.diff(run.poses, axis=0)
        repeat = np.all(step == 0, axis=1)
        stale_moving.append(repeat[~still[1:]])
        stale_still.append(repeat[still[1:]])
        size = np.hypot(step[:, 0], step[:, 1])
        onset = (size > JUMP_M) & ~np.vstack([np.zeros((1, size.shape[1]), dtype=bool), size[:-1] > JUMP_M])
        jumps += int(onset.sum())
        sizes += size[onset].tolist()
        total += size.size
    return {
        'stale_moving': float(np.mean(np.concatenate(stale_moving))),
        'stale_still': float(np.mean(np.concatenate(stale_still))) if sum(map(len, stale_still)) else float('nan'),
        'jumps_per_1000': 1000 * jumps / total,
        'jump_m': float(np.median(sizes)) if sizes else float('nan'),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog='python -m benchmarks.testbed_identification', description=__doc__)
    parser.add_argument('--more', type=Path, default=None, help='a folder of further .mat runs (fetched, in /tmp)')
    args = parser.parse_args(argv)
    runs = load_runs(default_files(args.more))
    if not runs:
        print('no runs: set VTUBE_REALDATA to the real recordings (robotarium-cbf4, robotarium-lines3) or give --more')
        return 2
    kept = [run for run in runs if not scaled_after_saving(run)]
    iterations = sum(r.poses.shape[0] * r.poses.shape[2] for r in kept)
    print(f'{len(kept)} runs, {iterations} robot-iterations; left out, commands scaled after saving:')
    print(''.join(f'    {run.name}\n' for run in runs if run not in kept), end='')
    print(f'new ({len(kept)} runs):')
    _print_dynamics(kept)
    print(f'old ({len(runs)} runs, as model version 1):')
    _print_dynamics(runs)
    print_poses(kept, runs)
    return 0


def _print_dynamics(runs: list[Run]) -> None:
    for channel, name in ((0, 'v'), (1, 'omega')):
        delay, lag, _ = fit_channel(runs, channel)
        each = np.array([fit_channel([r], channel)[:2] for r in runs if r.poses.shape[0] >= CLOSED_LOOP_STEPS])
        centroid = each[:, 0] + each[:, 1] / DT
        fits = per_robot(runs, channel, delay, lag)
        print(
            f'{name:5s}: delay {delay:.1f} it, lag {lag:.2f} s (centroid {delay + lag / DT:.1f} it, '
            f'{(delay * DT + lag):.3f} s); per run: delay median {np.median(each[:, 0]):.1f} '
            f'(p10-p90 {np.percentile(each[:, 0], 10):.1f}-{np.percentile(each[:, 0], 90):.1f}), '
            f'lag median {np.median(each[:, 1]):.2f} s, centroid median {np.median(centroid):.1f} it'
        )
        mid = np.nanmedian(fits, axis=0)
        sd = [_robust_sd(fits[np.isfinite(fits[:, j]), j]) for j in range(2)]
        extra = f', bias {mid[1]:+.4f} rad/s (sd {sd[1]:.4f})' if channel == 1 else ''
        print(f'       gain {mid[0]:.3f} (sd {sd[0]:.3f}; median and robust sd over {len(fits)} robot-runs){extra}')


def print_poses(runs: list[Run], old_runs: list[Run]) -> None:
    """The pose side on ``runs``, model version 1's figures (on ``old_runs``, its way) beside."""
    along, across, heading = pose_noise(runs)
    print(f'pose noise: {1000 * along:.2f} mm along, {1000 * across:.2f} mm across, {heading:.4f} rad heading')
    print(f'headings on a 0.001 rad grid: {100 * heading_quantum(runs):.1f} %')
    old, stale, stall = stale_and_jumps(old_runs), stale_by_motion(runs), stalls(runs)
    print(
        f'stale poses while driving: new {100 * stale["driving"]:.3f} % (runs p10-p90 {100 * stale["driving_p10"]:.3f}-'
        f'{100 * stale["driving_p90"]:.3f} %), old {100 * old["stale_moving"]:.2f} % (commanded above 5 mm/s)'
    )
    print(
        f'stale poses standing: new {100 * stale["stopped"]:.1f} % (below 2 mm/s), old {100 * old["stale_still"]:.1f} %'
        f' (commanded to stand); between 2 and 20 mm/s {100 * stale["between"]:.1f} %'
    )
    print(
        f'stalls: new {stall["per_1000"]:.2f} per 1000 robot-iterations driving, drove {stall["extra_steps"]:.1f} periods '
        f'more (median; p25-p75 {stall["extra_p25"]:.1f}-{stall["extra_p75"]:.1f}), {100 * stall["along"]:.0f} % of '
        f'the steps along the heading, {100 * stall["continued"]:.0f} % continued (no return), '
        f'{100 * stall["shared"]:.0f} % of the other fast robots stalled too; old: jumps '
        f'{old["jumps_per_1000"]:.2f} per 1000 robot-iterations, median {100 * old["jump_m"]:.1f} cm, random direction'
    )


def scaled_after_saving(run: Run) -> bool:
    """Whether the run's commands were scaled after saving in the quadrant x < 0, y > 0 (module docstring)."""
    rates, ok = measured(run)
    inside = (run.poses[:-1, 0] < 0) & (run.poses[:-1, 1] > 0)
    for channel, least in ((0, 0.02), (1, 0.2)):
        f = response(clipped(run.commands)[:-1, channel], 5.0, 0.19)
        y, gains = rates[:, channel], []
        for where in (inside, ~inside):
            chosen = ok & where & (np.abs(f) > least)
            gains.append(np.sum(f[chosen] * y[chosen]) / np.sum(f[chosen] ** 2) if chosen.sum() > 50 else np.nan)
        if abs(gains[0] / gains[1] - 1) > SCALED:  # NaN (too little motion in a part): not shown scaled
            return True
    return False


def motion(run: Run) -> tuple[np.ndarray, np.ndarray]:
    """Each robot's speed about pose k+1 (T-1, N: over the ``WINDOW`` poses either side) and whether a step of
    more than ``JUMP_M`` lies within that window."""
    xy, t = run.poses[:, :2], run.poses.shape[0]
    k = np.arange(1, t)
    lo, hi = np.clip(k - WINDOW, 0, t - 1), np.clip(k + WINDOW, 0, t - 1)
    speed = np.hypot(*(xy[hi] - xy[lo]).transpose(1, 0, 2)) / ((hi - lo)[:, None] * DT)
    big = np.pad(np.hypot(*np.diff(xy, axis=0).transpose(1, 0, 2)) > JUMP_M, ((WINDOW, WINDOW), (0, 0)))
    near = np.lib.stride_tricks.sliding_window_view(big, 2 * WINDOW + 1, axis=0).any(axis=-1)[: t - 1]
    return speed, near


def stale_by_motion(runs: list[Run]) -> dict[str, float]:
    """Stale-pose rates of robots actually driving, standing and in between, away from stalls (pooled, and the
    driving rate's p10-p90 over the runs)."""
    found: dict[str, list[np.ndarray]] = {'driving': [], 'stopped': [], 'between': []}
    for run in runs:
        repeat = np.all(np.diff(run.poses, axis=0) == 0, axis=1)
        speed, near = motion(run)
        driving, stopped = (speed >= DRIVING_MPS) & ~near, (speed < STOPPED_MPS) & ~near
        for name, where in (('driving', driving), ('stopped', stopped), ('between', ~driving & ~stopped & ~near)):
            found[name].append(repeat[where])
    each = [float(x.mean()) for x in found['driving'] if x.size]
    pooled = {name: float(np.mean(np.concatenate(x))) for name, x in found.items()}
    return pooled | {'driving_p10': float(np.percentile(each, 10)), 'driving_p90': float(np.percentile(each, 90))}


def stalls(runs: list[Run]) -> dict[str, float]:
    """Stalls of robots actually driving (a step over ``JUMP_M``) per 1000 of their robot-iterations, the periods they
    drove on (median, quartiles), the shares of those steps along the heading (|cos| > 0.9) and continued (two poses
    on, still at least the step away), and the share of the other robots as fast (``STALL_SPEED_MPS``) that stalled
    in the same iteration."""
    jumps, driving, extra, along, continued, shared = 0, 0, [], [], [], []
    for run in runs:
        p = run.poses
        step = np.diff(p, axis=0)
        size = np.hypot(step[:, 0], step[:, 1])
        onset = (size > JUMP_M) & ~np.vstack([np.zeros((1, size.shape[1]), dtype=bool), size[:-1] > JUMP_M])
        speed, near = motion(run)
        before = np.vstack([speed[:1].repeat(WINDOW + 1, axis=0), speed[: -WINDOW - 1]])  # the window ending at k
        driving += int(((before >= DRIVING_MPS) & ~(near & ~onset)).sum())
        for k, i in zip(*np.nonzero(onset & (before >= DRIVING_MPS)), strict=True):
            jumps += 1
            heading = p[k, 2, i]
            along.append(abs(step[k, 0, i] * np.cos(heading) + step[k, 1, i] * np.sin(heading)) > 0.9 * size[k, i])
            later = p[min(k + 2, len(p) - 1), :2, i] - p[k, :2, i]
            continued.append(np.hypot(*later) >= 0.9 * size[k, i])
            if before[k, i] >= STALL_SPEED_MPS:
                extra.append(size[k, i] / (before[k, i] * DT) - 1)
                others = np.arange(p.shape[2]) != i
                fast = others & (before[k] >= STALL_SPEED_MPS)
                shared += [bool(x) for x in onset[k, fast]]
    q25, q50, q75 = np.percentile(extra, [25, 50, 75]) if extra else (np.nan,) * 3
    return {
        'per_1000': 1000 * jumps / driving,
        'extra_steps': float(q50),
        'extra_p25': float(q25),
        'extra_p75': float(q75),
        'along': float(np.mean(along)) if along else float('nan'),
        'continued': float(np.mean(continued)) if continued else float('nan'),
        'shared': float(np.mean(shared)) if shared else float('nan'),
    }


if __name__ == '__main__':
    raise SystemExit(main())
