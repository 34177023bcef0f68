"""V2's misc utilities: random positions and poses."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.rps.utilities.misc import generate_random_poses, generate_random_positions


def test_random_positions_are_spaced_and_seeded_by_numpy() -> None:
    np.random.seed(3)
    points = generate_random_positions(8, spacing=0.5)
    gaps = np.hypot(*(points[:, :, None] - points[:, None, :]))[np.triu_indices(8, 1)]
    assert points.shape == (2, 8) and gaps.min() >= 0.5 and np.all(np.abs(points[0]) <= 1.5)
    np.random.seed(3)
    np.testing.assert_array_equal(generate_random_poses(8, spacing=0.5)[:2], points)
    with pytest.raises(AssertionError, match='Cannot fit 40 positions with spacing 0.50 m') as caught:
        generate_random_positions(40, spacing=0.5, width=2.0, height=2.0)
    assert caught.type is AssertionError  # V2's own type, not a subclass
