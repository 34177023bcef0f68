"""Exceptions of :mod:`robotarium_exp`: one base, :class:`RobotariumExpError`.

The package stands below :mod:`vtube_planning` in nothing (its ``rps`` part stands for a third-party contract and
imports nothing of ours), so its base is its own.
"""

from __future__ import annotations


class RobotariumExpError(Exception):
    """Base of every error :mod:`robotarium_exp` raises on purpose."""


class RobotariumError(RobotariumExpError, AssertionError):
    """Misuse of the Robotarium API (call order, shapes, robot counts).

    It subclasses ``AssertionError`` because that is what ``rps`` raises for the same mistakes (through ``assert``),
    so scripts that run on the testbed behave the same here; the messages say what to do instead.
    """


class ExperimentError(RobotariumExpError, ValueError):
    """An experiment that cannot be set up: initial conditions, scene, plan."""


class AnalysisError(RobotariumExpError, ValueError):
    """Trajectory data that cannot be read or analysed: missing topic, wrong format, truncated file, NaN poses."""
