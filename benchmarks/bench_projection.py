"""Projection of 10,000 points onto curved tubes: VirtualTube.project against a plain dense nearest-sample search.

Both run in this process on the same points; the script prints the time per call (median of repeats), the
worst arc-length error of each against the points' true coordinates, and the speed ratio.

    python -m benchmarks.bench_projection [--points 10000] [--repeats 7] [--spacing-m 0.01]
"""

from __future__ import annotations

import argparse
from functools import partial

import numpy as np

from benchmarks._timing import timed
from robotarium_exp.scene import load_scene
from vtube_planning import VirtualTube


def dense_nearest_sample(tube: VirtualTube, points: np.ndarray, spacing_m: float) -> np.ndarray:
    """Arc length of the nearest of the samples spaced ``spacing_m`` along the centre line (brute force)."""
    samples_l = np.linspace(0.0, tube.length_m, int(np.ceil(tube.length_m / spacing_m)) + 1)
    samples = tube.center_at(samples_l)
    xy = points.T
    best = np.empty(xy.shape[0], dtype=np.intp)
    chunk = max(1, 4_000_000 // samples.shape[0])
    for start in range(0, xy.shape[0], chunk):
        d2 = ((xy[start : start + chunk, None, :] - samples[None, :, :]) ** 2).sum(axis=2)
        best[start : start + chunk] = d2.argmin(axis=1)
    return samples_l[best]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--points', type=int, default=10_000)
    parser.add_argument('--repeats', type=int, default=7)
    parser.add_argument(
        '--spacing-m',
        type=float,
        default=None,
        help='dense sample spacing (default: L / 6000, about 1 cm on the paper scenes)',
    )
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    print(
        f'{"scene":<18} {"N":>6} {"project [ms]":>13} {"max |dl| [m]":>13} {"dense [ms]":>11} '
        f'{"max |dl| [m]":>13} {"samples":>8} {"ratio":>7}'
    )
    for name in ('D', 'B', 'robotarium_curve'):
        tube = load_scene(name).tube
        l_true = rng.uniform(0.0, tube.length_m, args.points)
        y_true = rng.uniform(-1.0, 1.0, args.points) * tube.half_width(l_true)
        points = (tube.center_at(l_true) + y_true[:, None] * tube.normal(l_true)).T
        spacing = args.spacing_m or tube.length_m / 6000
        tube.project(points[:, :10])  # build the k-d tree once, as every later call finds it built
        t_ours, proj = timed(partial(tube.project, points), args.repeats)
        t_dense, l_dense = timed(partial(dense_nearest_sample, tube, points, spacing), max(1, args.repeats // 3))
        err_ours = float(np.abs(proj.l_m - l_true).max())
        err_dense = float(np.abs(l_dense - l_true).max())
        samples = int(np.ceil(tube.length_m / spacing)) + 1
        print(
            f'{name:<18} {args.points:>6} {1e3 * t_ours:>13.2f} {err_ours:>13.1e} {1e3 * t_dense:>11.1f} '
            f'{err_dense:>13.1e} {samples:>8} {t_dense / t_ours:>6.1f}x'
        )


if __name__ == '__main__':
    main()
