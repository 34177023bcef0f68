"""What a tube generator is asked for: its checks, the room it derives, the reach of a cross-section to the map's
edge (against the distances to a rectangle's sides worked out by hand) and the ends of the path search."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vtube_planning.errors import TubeGenerationError
from vtube_planning.geometry.from_maps import generate
from vtube_planning.geometry.from_maps.tube_spec import TubeSpec
from vtube_planning.geometry.obstacles import Obstacles
from vtube_planning.geometry.workspace import Workspace

MAP = Workspace(0.0, 20.0, 0.0, 10.0, margin_m=0.5)


def spec(**options: object) -> TubeSpec:
    values: dict[str, object] = {'half_width_min_m': 0.5, 'half_width_max_m': 2.0, 'margin_m': 0.1, **options}
    return TubeSpec(MAP, Obstacles(), (1.0, 2.0), (19.0, 8.0), **values)  # type: ignore[arg-type]


def test_the_generator_exports_the_same_spec() -> None:
    assert generate.TubeSpec is TubeSpec


def test_the_room_is_the_narrowest_tube_the_margin_and_the_certificates_share() -> None:
    made = spec(slope_max=0.3, resolution_m=0.2)
    share = 1.3 * 0.5 * min(0.01, 0.125 * 0.5)
    assert made.certificate_share_m == pytest.approx(share)
    assert made.sample_m == pytest.approx(0.05)
    assert made.room_m == pytest.approx(0.5 + 0.1 + share + 0.025)


def test_a_cross_section_reaches_the_nearer_side_both_ways() -> None:
    points = np.array([[5.0, 3.0], [5.0, 3.0], [2.0, 5.0]])
    up = np.array([0.0, 1.0])
    diagonal = np.array([1.0, 1.0]) / math.sqrt(2.0)
    reach = spec().edge_reach(points, np.array([up, diagonal, [1.0, 0.0]]))
    # inside the margin the rectangle is [0.5, 19.5] x [0.5, 9.5]: up from y = 3 reaches 6.5, down 2.5
    # along the diagonal from (5, 3): down-left to y = 0.5 after 2.5 sqrt 2; across from x = 2: 1.5 to the left
    assert reach == pytest.approx([2.5, 2.5 * math.sqrt(2.0), 1.5])


def test_the_search_ends_lie_twice_the_lead_along_the_headings() -> None:
    assert spec().search_ends == ((1.0, 2.0), (19.0, 8.0))
    start, goal = spec(start_heading_deg=90.0, goal_heading_deg=0.0, lead_m=0.5).search_ends
    assert start == pytest.approx((1.0, 3.0))
    assert goal == pytest.approx((18.0, 8.0))


@pytest.mark.parametrize(
    ('options', 'named'),
    [
        ({'half_width_min_m': 0.0}, 'half_width_min_m must be a finite number > 0'),
        ({'margin_m': -0.1}, 'margin_m must be a finite number >= 0'),
        ({'start_heading_deg': math.nan}, 'start_heading_deg must be a finite number of degrees'),
        ({'half_width_max_m': 0.4}, 'half_width_min_m <= half_width_max_m'),
        ({'curvature_share': 1.0}, 'curvature_share < 1'),
    ],
)
def test_bad_limits_are_refused_naming_them(options: dict[str, object], named: str) -> None:
    with pytest.raises(TubeGenerationError, match=named):
        spec(**options)
