"""A rectangle a scene's tube must fit inside, with a margin (e.g. the Robotarium arena)."""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from vtube_planning._validate import is_real
from vtube_planning.errors import SceneError


@dataclass(frozen=True)
class Workspace:
    """A rectangle the tube must fit inside, with a margin (e.g. the Robotarium arena)."""

    x_min_m: float
    x_max_m: float
    y_min_m: float
    y_max_m: float
    margin_m: float = 0.0

    def __post_init__(self) -> None:
        values = [getattr(self, f.name) for f in fields(self)]
        if not all(is_real(v) for v in values):
            msg = f'workspace bounds must be finite numbers; got {values}.'
            raise SceneError(msg)
        if not (self.x_min_m < self.x_max_m and self.y_min_m < self.y_max_m and self.margin_m >= 0):
            msg = f'workspace needs x_min < x_max, y_min < y_max and margin >= 0; got {self}.'
            raise SceneError(msg)

    def clearance(self, points_m: np.ndarray) -> np.ndarray:
        """Signed distance of (k, 2) points to the rectangle's edge (positive inside), (k,)."""
        x, y = points_m[:, 0], points_m[:, 1]
        clearance: np.ndarray = np.minimum.reduce(
            [x - self.x_min_m, self.x_max_m - x, y - self.y_min_m, self.y_max_m - y]
        )
        return clearance
