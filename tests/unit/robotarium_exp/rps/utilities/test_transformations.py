"""V2's transformations: the uni-to-si mapping."""

from __future__ import annotations

import numpy as np
import pytest


def test_uni_to_si_mapping_gives_axle_positions() -> None:
    """V2's second function of ``create_uni_to_si_mapping`` maps projected points back to the axles (2xN)."""
    from robotarium_exp.rps.utilities.transformations import create_si_to_uni_mapping, create_uni_to_si_mapping

    rng = np.random.default_rng(4)
    poses = np.vstack([rng.uniform(-1, 1, (2, 5)), rng.uniform(-np.pi, np.pi, 5)])
    _, points_of = create_si_to_uni_mapping(projection_distance=0.07)
    _, axles_of = create_uni_to_si_mapping(projection_distance=0.07)
    axles = axles_of(poses, points_of(poses))
    assert axles.shape == (2, 5)
    np.testing.assert_allclose(axles, poses[:2], atol=1e-15)
    with pytest.raises(AssertionError, match=r'si_states must be 2xN. Got 3x5.') as caught:
        axles_of(poses, poses)
    assert caught.type is AssertionError  # V2's own type, not a subclass
