"""Pair distances over each pair's common frames, against a plain loop over pairs and frames."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.analysis import distances
from robotarium_exp.analysis.distances import pair_distances


def loop(positions: np.ndarray, radius: float | None):
    """Each pair's common frames, min, argmin and frames below the radius, and each frame's min, by plain loops."""
    steps, _, n = positions.shape
    out, frame_min = [], np.full(steps, np.inf)
    for i in range(n):
        for j in range(i + 1, n):
            ds = [(np.hypot(*(positions[t, :, i] - positions[t, :, j])), t) for t in range(steps)]
            ds = [(d, t) for d, t in ds if np.isfinite(d)]
            for d, t in ds:
                frame_min[t] = min(frame_min[t], d)
            best = min(ds) if ds else (np.nan, -1)
            out.append((len(ds), best[0], best[1], sum(d < radius for d, _ in ds) if radius else 0))
    return out, np.where(np.isfinite(frame_min), frame_min, np.nan)


@pytest.mark.parametrize('block', [10**9, 7])  # one block, and blocks of a few frames
def test_pairs_with_holes_equal_a_plain_loop(monkeypatch, block: int) -> None:
    monkeypatch.setattr(distances, 'BLOCK_ELEMENTS', block)
    rng = np.random.default_rng(3)
    positions = rng.uniform(-1, 1, (40, 2, 5))
    for step, robot in np.argwhere(rng.random((40, 5)) < 0.3):  # robots drop out
        positions[step, :, robot] = np.nan
    positions[:, :, 4] = np.nan
    positions[:3, :, 4] = 0.0  # robot 4 seen only in the first three frames
    result = pair_distances(positions, 0.5)
    expected, frame_min = loop(positions, 0.5)
    assert list(zip(result.first, result.second, strict=True)) == [(i, j) for i in range(5) for j in range(i + 1, 5)]
    for k, (common, best, frame, below) in enumerate(expected):
        assert result.common_frames[k] == common and result.below[k] == below
        assert result.min_m[k] == pytest.approx(best, nan_ok=True) and result.min_frame[k] == frame
    np.testing.assert_allclose(result.frame_min_m, frame_min)
    assert result.frames_below == int(np.count_nonzero(frame_min < 0.5)) > 0  # a frame's closest pair decides


def test_without_a_radius_nothing_is_below_and_a_pair_never_together() -> None:
    positions = np.full((4, 2, 3), np.nan)
    positions[:2, :, 0] = [0.0, 0.0]
    positions[:2, :, 1] = [0.3, 0.4]  # 0.5 m from robot 0 in frames 0 and 1
    positions[2:, :, 2] = 1.0  # robot 2 only in frames 2 and 3
    result = pair_distances(positions)
    assert result.common_frames.tolist() == [2, 0, 0] and np.isnan(result.min_m[1:]).all()
    assert result.min_m[0] == pytest.approx(0.5) and result.min_frame[0] == 0
    assert result.min_frame.tolist()[1:] == [-1, -1] and result.below.tolist() == [0, 0, 0]
    assert result.frames_below == 0 and np.isnan(result.frame_min_m[2:]).all()
    one = pair_distances(np.zeros((5, 2, 1)))
    assert one.first.size == 0 and np.isnan(one.frame_min_m).all()
