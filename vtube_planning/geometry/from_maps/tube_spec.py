"""What the generator of a tube from a map is asked for (`TubeSpec`): the map, start and goal, the tube's limits,
and what follows from them (the room the narrowest tube needs, the reach of a cross-section to the map's edge).

Shared by the path search (`vtube_planning.geometry.from_maps.centre_path`) and the generator
(`vtube_planning.geometry.from_maps.generate`, which exports it too), below both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vtube_planning._validate import is_positive, is_real
from vtube_planning.errors import TubeGenerationError
from vtube_planning.geometry.obstacles import Obstacles
from vtube_planning.geometry.workspace import Workspace

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class TubeSpec:
    """What to generate: the map (its rectangle and obstacles), start and goal, and the tube's limits.

    Attributes
    ----------
    bounds
        The map's rectangle; its ``margin_m`` is kept between the tube's boundaries and the map's edge.
    obstacles
        Discs, polygons and occupancy images.
    start_m, goal_m
        Where the centre curve starts and ends.
    half_width_min_m, half_width_max_m
        The narrowest half-width accepted (a passage with less room is refused) and the widest generated.
    margin_m
        Kept between the tube's walls and every obstacle.
    turn_radius_min_m
        The smallest radius of curvature of the centre curve (the planner's (p2) with (p4) need r_t >= v_min^2 /
        a_n).
    curvature_share
        lambda <= curvature_share x r_t, below 1: regularity with room to spare.
    slope_max
        The largest |d lambda / dl|.
    resolution_m
        The grid of the path search.
    start_heading_deg, goal_heading_deg, lead_m
        Optional headings at the start and the goal, each held straight for at least ``lead_m`` (a start
        formation in rows across the tube, parking lanes beyond its exit); a heading with ``lead_m`` 0 leaves the
        lead to the generator, which fits the shortest that works (`LEADS`).
    """

    bounds: Workspace
    obstacles: Obstacles
    start_m: tuple[float, float]
    goal_m: tuple[float, float]
    half_width_min_m: float
    half_width_max_m: float
    margin_m: float = 0.0
    turn_radius_min_m: float = 0.0
    curvature_share: float = 0.8
    slope_max: float = 0.3
    resolution_m: float = 0.1
    start_heading_deg: float | None = None
    goal_heading_deg: float | None = None
    lead_m: float = 0.0

    def __post_init__(self) -> None:
        for name in ('half_width_min_m', 'half_width_max_m', 'resolution_m', 'curvature_share', 'slope_max'):
            if not is_positive(getattr(self, name)):
                msg = f'tube generation: {name} must be a finite number > 0; got {getattr(self, name)!r}.'
                raise TubeGenerationError(msg)
        for name in ('start_heading_deg', 'goal_heading_deg'):
            if getattr(self, name) is not None and not is_real(getattr(self, name)):
                msg = f'tube generation: {name} must be a finite number of degrees; got {getattr(self, name)!r}.'
                raise TubeGenerationError(msg)
        for name in ('margin_m', 'turn_radius_min_m', 'lead_m'):
            value = getattr(self, name)
            if not is_real(value) or value < 0.0:
                msg = f'tube generation: {name} must be a finite number >= 0; got {value!r}.'
                raise TubeGenerationError(msg)
        if self.half_width_max_m < self.half_width_min_m or self.curvature_share >= 1.0:
            msg = (
                'tube generation needs half_width_min_m <= half_width_max_m and curvature_share < 1; got '
                f'{self.half_width_min_m}, {self.half_width_max_m}, {self.curvature_share}.'
            )
            raise TubeGenerationError(msg)
        for name in ('start_m', 'goal_m'):
            point = getattr(self, name)
            if len(point) != 2 or not all(is_real(v) for v in point):
                msg = f'tube generation: {name} must be [x, y], finite; got {point!r}.'
                raise TubeGenerationError(msg)
        apart = math.dist(self.start_m, self.goal_m)
        if apart < 2.0 * self.resolution_m:
            msg = (
                f'tube generation: start_m and goal_m are {apart:.3g} m apart ({list(self.start_m)} and '
                f'{list(self.goal_m)}), less than two cells of the search grid (resolution_m = {self.resolution_m:g}); '
                'put the goal where the tube should end.'
            )
            raise TubeGenerationError(msg)

    @property
    def headed(self) -> bool:
        """Whether a heading is given at the start or the goal."""
        return self.start_heading_deg is not None or self.goal_heading_deg is not None

    @property
    def search_ends(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """Where the path search starts and ends: the start and goal, or the ends of their straight leads (twice
        ``lead_m`` along the heading given: the arc that turns off a lead takes at most half of it)."""

        def along(point: tuple[float, float], heading: float | None, sign: float) -> tuple[float, float]:
            if heading is None:
                return point
            reach = sign * 2.0 * self.lead_m
            return point[0] + reach * math.cos(math.radians(heading)), point[1] + reach * math.sin(
                math.radians(heading)
            )

        return along(self.start_m, self.start_heading_deg, 1.0), along(self.goal_m, self.goal_heading_deg, -1.0)

    @property
    def certificate_share_m(self) -> float:
        """What the obstacle certificate needs beyond the wall ((1 + slope) x half its sample spacing)."""
        return (1.0 + self.slope_max) * 0.5 * min(0.01, 0.125 * self.half_width_min_m)

    @property
    def sample_m(self) -> float:
        """The spacing of the width's samples along the centre curve."""
        return 0.25 * self.resolution_m

    @property
    def room_m(self) -> float:
        """The clearance the narrowest tube needs around its centre: lambda_min, the margin, and what the
        certificate and the width's samples take."""
        return self.half_width_min_m + self.margin_m + self.certificate_share_m + 0.5 * self.sample_m

    def edge_reach(self, points_m: FloatArray, normals: FloatArray) -> FloatArray:
        """How far (k,) a cross-section through each of (k, 2) points along its (k, 2) unit normal can reach, both
        ways, before it leaves the map less its margin: the map's edge bounds the width across the tube only (a
        tube may meet the edge head-on at its start and goal)."""
        b, m = self.bounds, self.bounds.margin_m
        low, high = np.array([b.x_min_m + m, b.y_min_m + m]), np.array([b.x_max_m - m, b.y_max_m - m])

        def along(direction: FloatArray) -> FloatArray:  # to the rectangle's side the direction points at
            with np.errstate(divide='ignore', invalid='ignore'):
                side = np.where(direction > 0, high, low)
                steps = np.where(direction != 0, (side - points_m) / direction, np.inf)
            reach: FloatArray = steps.min(axis=1)
            return reach

        return np.minimum(along(normals), along(-normals))
