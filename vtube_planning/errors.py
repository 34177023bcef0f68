"""Exceptions of `vtube_planning`.

Every exception derives from [`VtubeError`][vtube_planning.errors.VtubeError] and from the builtin that describes it
best, so callers can catch either ``VtubeError`` (everything from this package) or ``ValueError`` (bad input of any
origin).
"""

from __future__ import annotations


class VtubeError(Exception):
    """Base class of every error raised by `vtube_planning`."""


class ParamsError(VtubeError, ValueError):
    """Swarm or planning parameters out of their valid range."""


class TubeError(VtubeError, ValueError):
    """A virtual tube that is malformed or violates a regularity condition."""


class SceneError(VtubeError, ValueError):
    """A scene file that cannot be read, or that names unknown or missing fields."""


class ShapeError(VtubeError, ValueError):
    """An array argument of the wrong shape or with non-finite entries."""


class PlanError(VtubeError, ValueError):
    """A planning problem that is infeasible or malformed, or a plan file that cannot be read."""


class SolverError(VtubeError, RuntimeError):
    """The optimisation solver failed on a problem that was shown feasible before it ran."""


class LogError(VtubeError, ValueError):
    """A trajectory log that cannot be read."""


class TubeGenerationError(VtubeError, ValueError):
    """No certified tube for an obstacle map (`vtube_planning.geometry.from_maps.generate`): the message names the place
    and the reason."""
