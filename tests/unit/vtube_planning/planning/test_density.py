"""The predicted density: the footprint and the two predictive readings of (p7) by hand."""

from __future__ import annotations

import numpy as np
import pytest

from vtube_planning.errors import ParamsError
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.onboard.density import swarm_area
from vtube_planning.planning.density import footprint, predicted_density


def step_tube() -> VirtualTube:
    """Straight, half-width 2 m for 10 m, then 1 m (smooth over 1 m) for the remaining 19 m."""
    width = WidthProfile(
        2.0, (WidthPart('constant', 10.0), WidthPart('smooth', 1.0, to_m=1.0), WidthPart('constant', 19.0))
    )
    return VirtualTube(ArcPath((ArcPiece(30.0),)), width)


def test_footprint_holds_n_over_rho_centred_by_area() -> None:
    tube = step_tube()
    back, front = footprint(tube, np.array([5.0, 22.0]), np.array([0.5, 0.25]), 10)
    np.testing.assert_allclose(back, [5.0 - 2.5, 22.0 - 10.0])  # 20 m^2 / 4 m wide, 40 m^2 / 2 m wide
    np.testing.assert_allclose(front, [5.0 + 2.5, 22.0 + 10.0])  # past L, on the straight extension
    np.testing.assert_allclose(swarm_area(tube, back, front, 0.0), [20.0, 40.0])


def test_local_width_prediction_scales_with_the_width_ratio() -> None:
    tube = step_tube()
    rho = predicted_density(tube, np.array([2.0, 9.5, 15.0]), 0.3, 20, 3.0, 'local_width')
    np.testing.assert_allclose(rho, [0.3, 0.6, 0.3])


def test_rigid_shift_prediction_of_a_swarm_moving_into_the_narrow_part() -> None:
    tube = step_tube()
    # 8 robots at 1 robot/m^2 centred at l = 5 occupy [4, 6] (8 m^2 at 4 m wide); shifted by 8 m to [12, 14]
    rho = predicted_density(tube, np.array([5.0]), 1.0, 8, 8.0, 'rigid_shift')
    assert rho[0] == pytest.approx(8 / (2 * 1.0 * 2.0))
    # in a constant part nothing changes, whatever the reading
    for model in ('local_width', 'rigid_shift'):
        assert predicted_density(tube, np.array([20.0]), 0.4, 8, 2.0, model)[0] == pytest.approx(0.4)
    with pytest.raises(ParamsError, match='predictive model must be one of'):
        predicted_density(tube, np.array([1.0]), 0.4, 8, 2.0, 'psychic')
