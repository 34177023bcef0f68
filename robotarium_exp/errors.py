"""Exceptions of `robotarium_exp`: one base, [`RobotariumExpError`][robotarium_exp.errors.RobotariumExpError].

The package stands below `vtube_planning` in nothing, so its base is its own. Its ``rps`` part stands for a
third-party contract: it raises the official's ``AssertionError`` where the official asserts, and its own
[`RobotariumError`][robotarium_exp.rps.errors.RobotariumError] (an ``AssertionError`` too) for the refusals the
official does not make.
"""

from __future__ import annotations


class RobotariumExpError(Exception):
    """Base of every error `robotarium_exp` raises on purpose."""


class SpecError(RobotariumExpError, ValueError):
    """A [`RobotariumSpec`][robotarium_exp.spec.RobotariumSpec] with impossible numbers (an empty arena, a time step <=
    0)."""


class ExperimentError(RobotariumExpError, ValueError):
    """An experiment that cannot be set up: initial conditions, scene, plan."""


class AnalysisError(RobotariumExpError, ValueError):
    """Trajectory data that cannot be read or analysed: missing topic, wrong format, truncated file, NaN poses."""
